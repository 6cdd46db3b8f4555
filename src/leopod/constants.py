"""Physical and conventional constants, each with its unit (in the name) and its source.

Signal frequencies live in :mod:`leopod.signals`, not here.
"""

#: Speed of light in vacuum [m/s]. IERS Conventions 2010, Table 1.1 (defining constant).
C_LIGHT_M_S = 299_792_458.0

#: Geocentric gravitational constant, TT-compatible (orbits are integrated in TT), incl. the
#: atmosphere [m^3/s^2]. IERS Conventions 2010, Table 1.1 (TCG-compatible value: 3.986004418e14).
GM_EARTH_M3_S2 = 3.986004415e14

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

#: BeiDou time (BDT) minus GPS time [s], exact and leap-second free: BDT started at
#: 2006-01-01 00:00:00 UTC (BDS-SIS-ICD-B1I-3.0, time system), when GPST - UTC was 14 s
#: (GPST began at 1980-01-06 00:00:00 UTC, IS-GPS-200; TAI - UTC = 33 s from 2006-01-01,
#: IERS Bulletin C).
BDT_MINUS_GPST_S = -14.0

#: Galileo system time (GST) minus GPS time [s] as labels: GST started at 1999-08-22
#: 00:00:00 UT, 13 s ahead of UTC (Galileo OS SIS ICD 2.0, GST definition), which is GPST
#: at that instant. The physical GST-GPST offset (GGTO, a few ns) is not a label offset.
GST_MINUS_GPST_S = 0.0

#: TT minus TAI [s]. IERS Conventions 2010, Chapter 10.
TT_MINUS_TAI_S = 32.184

#: Julian date of J2000.0 (2000-01-01 12:00 TT) [d]. IERS Conventions 2010, Chapter 5.
JD_J2000 = 2_451_545.0

#: Astronomical unit [m]. IAU 2012 Resolution B2 (defining value).
AU_M = 149_597_870_700.0

#: Solar radiation pressure at 1 AU on a fully absorbing surface [N/m²] (solar constant
#: 1367 W/m² / c). Montenbruck & Gill, Satellite Orbits (2000), sec. 3.4.1.
SOLAR_PRESSURE_1AU_N_M2 = 4.56e-6

#: Radius of the Sun for the conical shadow model [m]. Montenbruck & Gill (2000), sec. 3.4.2.
R_SUN_M = 6.96e8

#: Heliocentric gravitational constant, TDB-compatible [m³/s²]. IERS Conventions 2010, Table 1.1.
GM_SUN_M3_S2 = 1.32712442099e20

#: Lunar gravitational constant [m³/s²]: DE421 value 4902.800066 km³/s² (Folkner et al. 2008).
GM_MOON_M3_S2 = 4.902800066e12

#: Earth's angular momentum per unit mass, along the GCRF Z axis [m²/s]. IERS 2010 sec. 10.3.
EARTH_ANGULAR_MOMENTUM_M2_S = 9.8e8

#: Rate of the Earth rotation angle [rad/s]: 2π · 1.00273781191135448 per UT1 day.
#: IERS Conventions 2010, eq. (5.15).
ERA_RATE_RAD_S = 2.0 * 3.141592653589793 * 1.00273781191135448 / SECONDS_PER_DAY

#: Height of the permanent tide H0 [m] (zero-frequency degree-2 tide). IERS 2010 eq. (6.14).
H0_PERMANENT_TIDE_M = -0.31460
