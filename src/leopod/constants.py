"""Physical and conventional constants, each with its unit (in the name) and its source.

Signal frequencies live in :mod:`leopod.gnss.signals`, not here.
"""

#: Speed of light in vacuum [m/s]. IERS Conventions 2010, Table 1.1 (defining constant).
C_LIGHT_M_S = 299_792_458.0

#: Geocentric gravitational constant, TT-compatible, incl. atmosphere [m^3/s^2].
#: IERS Conventions 2010, Table 1.1.
GM_EARTH_M3_S2 = 3.986004418e14

#: Nominal mean angular velocity of the Earth [rad/s]. IERS Conventions 2010, Table 1.1.
OMEGA_EARTH_RAD_S = 7.292115e-5

#: Earth angular velocity used by GPS for the Sagnac/earth-rotation correction [rad/s].
#: IS-GPS-200 (WGS 84 value).
OMEGA_EARTH_WGS84_RAD_S = 7.2921151467e-5

#: Equatorial radius of the Earth [m]. IERS Conventions 2010, Table 1.1 (GRS80/TOPEX value).
R_EARTH_EQUATOR_M = 6_378_136.6

#: Inverse flattening of the Earth. IERS Conventions 2010, Table 1.1.
INV_FLATTENING_EARTH = 298.25642

#: WGS 84 semi-major axis [m] and inverse flattening (NIMA TR8350.2), for geodetic latitude.
WGS84_A_M = 6_378_137.0
WGS84_INV_F = 298.257223563

#: Seconds per day [s].
SECONDS_PER_DAY = 86_400.0

#: GPS time minus TAI [s] (constant by definition of GPS time).
GPST_MINUS_TAI_S = -19.0

#: TT minus TAI [s]. IERS Conventions 2010, Chapter 10.
TT_MINUS_TAI_S = 32.184
