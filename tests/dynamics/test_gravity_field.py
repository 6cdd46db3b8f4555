"""Tests of leopod.dynamics.gravity_field and its sums (leopod.dynamics.spherical_harmonics).

Authorities: analytic point-mass and J2 fields; an independent brute-force potential summed in
50-120 significant digits (``decimal``) from the explicit Legendre polynomial sum, itself
checked against ``scipy.special.lpmv``, differentiated by central finite differences; finite
differences of the tested acceleration; Laplace's equation; two independent real models
(EGM2008, GGM05S); the WGS 84 normal gravity formula (NIMA TR8350.2).
"""

from __future__ import annotations

from decimal import Decimal, localcontext
from functools import lru_cache
from math import comb, factorial

import numpy as np
import pytest
import xarray as xr
from scipy.special import lpmv

from leopod.constants import OMEGA_EARTH_WGS84_RAD_S, WGS84_A_M, WGS84_INV_F
from leopod.dynamics.gravity_field import GravityField, decimal_year
from leopod.dynamics.spherical_harmonics import acceleration_sums, field_sums
from leopod.io.icgem import read_icgem

# test inputs: the GM and radius of the EGM2008 header (any values would do)
GM_M3_S2 = 3.986004415e14
RADIUS_M = 6378136.3
R_LEO_M = 6878136.3  # 500 km altitude

# WGS 84 normal gravity on the ellipsoid (Somigliana), NIMA TR8350.2 (3rd ed., 2000), eq. 4-1
WGS84_GAMMA_E_M_S2 = 9.7803253359
WGS84_K = 0.00193185265241
WGS84_E2 = 0.00669437999013


def _sph(r_m: float, colat_rad: float, lon_rad: float) -> np.ndarray:
    """Cartesian position from radius, colatitude, longitude."""
    return r_m * np.array([np.sin(colat_rad) * np.cos(lon_rad),
                           np.sin(colat_rad) * np.sin(lon_rad), np.cos(colat_rad)])


# generic LEO, 1e-6 rad from the north pole, on the south polar axis, on the equator, 200 km
POINTS_M = np.array([
    _sph(R_LEO_M, 0.92, 2.1),
    _sph(R_LEO_M, 1e-6, 0.4),
    [0.0, 0.0, -6_600_000.0],
    _sph(7_000_000.0, np.pi / 2, -1.0),
    [RADIUS_M + 200e3, 0.0, 0.0],
])


def _dataset(c: np.ndarray, s: np.ndarray, **attrs) -> xr.Dataset:
    """A Dataset shaped like the output of read_icgem."""
    size = c.shape[0]
    base = {"gm_m3_s2": GM_M3_S2, "radius_m": RADIUS_M, "max_degree": size - 1,
            "modelname": "TEST", "tide_system": "zero_tide", "time_variable_terms": ""}
    return xr.Dataset({"C": (("n", "m"), c), "S": (("n", "m"), s)},
                      coords={"n": np.arange(size), "m": np.arange(size)},
                      attrs={**base, **attrs})


def _synthetic(degree: int, seed: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """Random coefficients with a Kaula-like decay 1e-5/n², C00 = 1 and an Earth-like C20."""
    rng = np.random.default_rng(seed)
    n = np.arange(degree + 1)[:, None]
    m = np.arange(degree + 1)[None, :]
    sigma = 1e-5 / np.maximum(n, 1) ** 2
    c = np.where(m <= n, rng.normal(size=n.shape[:1] * 2) * sigma, 0.0)
    s = np.where((m <= n) & (m > 0), rng.normal(size=n.shape[:1] * 2) * sigma, 0.0)
    c[0, 0] = 1.0
    if degree >= 2:
        c[2, 0] = -4.84165e-4
    return c, s


# ------------------------------------------------------ independent brute-force reference


@lru_cache(maxsize=4)
def _legendre_terms(degree: int, prec: int) -> dict:
    """(n, m) -> [(power, coefficient)] of N̄nm dᵐPn/dtᵐ(t) = Σ coefficient t^power.

    Explicit sum Pn(t) = 2⁻ⁿ Σ_k (−1)ᵏ C(n, k) C(2n − 2k, n) t^(n − 2k) (Abramowitz & Stegun
    22.3.8) differentiated m times in exact integers; N̄nm = sqrt((2 − δm0)(2n + 1)(n − m)!/
    (n + m)!) (Heiskanen & Moritz 1967, eq. 1-73). No recursion is shared with the code tested.
    """
    with localcontext() as ctx:
        ctx.prec = prec
        out = {}
        for n in range(degree + 1):
            for m in range(n + 1):
                norm = (Decimal((1 if m == 0 else 2) * (2 * n + 1) * factorial(n - m))
                        / Decimal(factorial(n + m))).sqrt()
                terms = []
                for k in range(n // 2 + 1):
                    power = n - 2 * k
                    if power < m:
                        break
                    coef = ((-1) ** k * comb(n, k) * comb(2 * n - 2 * k, n) * factorial(power)
                            // factorial(power - m))
                    terms.append((power - m, Decimal(coef) / Decimal(2) ** n * norm))
                out[n, m] = terms
        return out


def _ref_potential(pos: list[Decimal], c: np.ndarray, s: np.ndarray, prec: int) -> Decimal:
    """U = GM/R Σ (R/r)^(n+1) N̄nm dᵐPn(t) [C̄ Re + S̄ Im]((x + i y)/r)ᵐ, t = z/r, in Decimal.

    Uses Pnm(t) cos mλ = dᵐPn(t) (1 − t²)^(m/2) cos mλ = dᵐPn(t) Re((x + i y)/r)ᵐ
    (no Condon-Shortley phase, as in geodesy).
    """
    degree = c.shape[0] - 1
    terms = _legendre_terms(degree, prec)
    with localcontext() as ctx:
        ctx.prec = prec
        x, y, z = pos
        r = (x * x + y * y + z * z).sqrt()
        t = z / r
        t_pow = [Decimal(1)]
        cos_m, sin_m = [Decimal(1)], [Decimal(0)]
        for _ in range(degree):
            t_pow.append(t_pow[-1] * t)
            cos_m.append(cos_m[-1] * x / r - sin_m[-1] * y / r)
            sin_m.append(sin_m[-1] * x / r + cos_m[-2] * y / r)
        radius = Decimal(repr(RADIUS_M))
        total, ratio = Decimal(0), radius / r
        for n in range(degree + 1):
            degree_sum = Decimal(0)
            for m in range(n + 1):
                if c[n, m] == 0.0 and s[n, m] == 0.0:
                    continue
                p_nm = sum(coef * t_pow[power] for power, coef in terms[n, m])
                degree_sum += p_nm * (Decimal(repr(float(c[n, m]))) * cos_m[m]
                                      + Decimal(repr(float(s[n, m]))) * sin_m[m])
            total += ratio ** (n + 1) * degree_sum
        return Decimal(repr(GM_M3_S2)) / radius * total


def _reference(pos_m: np.ndarray, c: np.ndarray, s: np.ndarray, prec: int, hessian: bool
               ) -> tuple[float, np.ndarray, np.ndarray]:
    """Potential, acceleration and (optionally) gradient by central differences of the Decimal
    potential with a 1 mm step: truncation (h/r)² ~ 1e-20 relative, round-off far below 1e-20.
    """
    with localcontext() as ctx:
        ctx.prec = prec
        base = [Decimal(repr(float(v))) for v in pos_m]
        step = Decimal("0.001")

        def pot(*shifts: tuple[int, int]) -> Decimal:
            p = list(base)
            for axis, sign in shifts:
                p[axis] += sign * step
            return _ref_potential(p, c, s, prec)

        u0 = pot()
        plus = [pot((i, 1)) for i in range(3)]
        minus = [pot((i, -1)) for i in range(3)]
        acc = np.array([float((plus[i] - minus[i]) / (2 * step)) for i in range(3)])
        grad = np.full((3, 3), np.nan)
        if hessian:
            for i in range(3):
                grad[i, i] = float((plus[i] - 2 * u0 + minus[i]) / step ** 2)
                for j in range(i + 1, 3):
                    mixed = (pot((i, 1), (j, 1)) - pot((i, 1), (j, -1))
                             - pot((i, -1), (j, 1)) + pot((i, -1), (j, -1)))
                    grad[i, j] = grad[j, i] = float(mixed / (4 * step ** 2))
        return float(u0), acc, grad


def test_reference_legendre_matches_scipy():
    # authority: scipy.special.lpmv (Condon-Shortley phase (−1)^m removed), double precision
    t = 0.37
    terms = _legendre_terms(30, 50)
    for n, m in [(2, 0), (5, 3), (17, 9), (30, 0), (30, 15), (30, 30)]:
        ref = (np.sqrt((1 if m == 0 else 2) * (2 * n + 1) * factorial(n - m) / factorial(n + m))
               * (-1) ** m * lpmv(m, n, t))
        ours = float(sum(coef * Decimal(t) ** p for p, coef in terms[n, m])) \
            * (1 - t * t) ** (m / 2)
        assert ours == pytest.approx(ref, rel=1e-12, abs=1e-14)


# ----------------------------------------------------------------------- analytic fields


def test_point_mass():
    # authority: analytic a = −GM r/r³, ∂a/∂r = GM (3 r rᵀ/r⁵ − I/r³), U = GM/r
    field = GravityField(_dataset(np.ones((1, 1)), np.zeros((1, 1))), 0)
    acc, grad = field.acceleration_and_gradient(POINTS_M)
    r = np.linalg.norm(POINTS_M, axis=1)
    acc_ref = -GM_M3_S2 * POINTS_M / r[:, None] ** 3
    grad_ref = GM_M3_S2 * (3 * np.einsum("ni,nj->nij", POINTS_M, POINTS_M) / r[:, None, None] ** 5
                           - np.eye(3) / r[:, None, None] ** 3)
    np.testing.assert_allclose(acc, acc_ref, rtol=0, atol=1e-14 * 10.0)
    np.testing.assert_allclose(grad, grad_ref, rtol=0, atol=1e-14 * 3e-6)
    np.testing.assert_allclose(field.potential(POINTS_M), GM_M3_S2 / r, rtol=1e-15)
    np.testing.assert_allclose(field.acceleration(POINTS_M), acc, rtol=0, atol=1e-15)


def test_j2_closed_form():
    # authority: Vallado (2013) sec. 8.6.1 (p. 594), with J2 = −√5 C̄20:
    # a = −GM/r³ r − 3/2 J2 GM R²/r⁵ [x (1 − 5z²/r²), y (1 − 5z²/r²), z (3 − 5z²/r²)]
    j2 = 1.0826359e-3
    c = np.zeros((3, 3))
    c[0, 0], c[2, 0] = 1.0, -j2 / np.sqrt(5.0)
    field = GravityField(_dataset(c, np.zeros((3, 3))), 2)
    x, y, z = POINTS_M.T
    r = np.linalg.norm(POINTS_M, axis=1)
    k = -1.5 * j2 * GM_M3_S2 * RADIUS_M ** 2 / r ** 5
    zz = 5 * z ** 2 / r ** 2
    acc_j2 = np.stack([k * x * (1 - zz), k * y * (1 - zz), k * z * (3 - zz)], axis=1)
    acc_ref = -GM_M3_S2 * POINTS_M / r[:, None] ** 3 + acc_j2
    np.testing.assert_allclose(field.acceleration(POINTS_M), acc_ref, rtol=0, atol=1e-14)
    non_spherical = GravityField(_dataset(c, np.zeros((3, 3))), 2, central_term=False)
    np.testing.assert_allclose(non_spherical.acceleration(POINTS_M), acc_j2, rtol=0,
                               atol=1e-16)


# ------------------------------------------------------------------------- brute force


@pytest.mark.parametrize("central_term", [True, False])
def test_brute_force_degree_30(central_term):
    # authority: the Decimal brute-force potential (60 digits) and its central differences
    c, s = _synthetic(30)
    field = GravityField(_dataset(c, s), 30, central_term=central_term)
    c_ref = c.copy()
    c_ref[0, 0] = 1.0 if central_term else 0.0
    acc, grad = field.acceleration_and_gradient(POINTS_M)
    for k, pos in enumerate(POINTS_M):  # includes 1e-6 rad from the pole, the axis, the equator
        u_ref, acc_ref, grad_ref = _reference(pos, c_ref, s, prec=60, hessian=True)
        assert abs(field.potential(pos) - u_ref) <= 1e-14 * abs(u_ref)
        # stated tolerance: 1e-13 of |a| (m/s²) for the acceleration, 1e-12 of |∂a/∂r| (1/s²)
        assert np.abs(acc[k] - acc_ref).max() <= 1e-13 * np.linalg.norm(acc_ref)
        assert np.abs(grad[k] - grad_ref).max() <= 1e-12 * np.linalg.norm(grad_ref)


def test_brute_force_degree_120():
    # authority: the Decimal brute-force potential (120 digits: the explicit sums cancel up to
    # ~50 digits at degree 120) and its central differences; required accuracy 1e-12 of |a|
    c, s = _synthetic(120, seed=7)
    c[0, 0] = 0.0  # non-spherical part alone: the hardest relative test
    field = GravityField(_dataset(c, s), 120, central_term=False)
    for pos in POINTS_M[:2]:  # generic LEO and 1e-6 rad from the pole
        _, acc_ref, _ = _reference(pos, c, s, prec=120, hessian=False)
        assert np.abs(field.acceleration(pos) - acc_ref).max() <= 1e-13 * np.linalg.norm(acc_ref)


# ---------------------------------------------------------------------- gradient checks


def test_gradient_finite_differences_symmetric_laplace():
    # authority: central differences of the tested acceleration (10 m step: truncation
    # (h/r)² ~ 2e-12, round-off 1e-16 |a|/h ~ 1e-10 of |∂a/∂r|); symmetry; Laplace ΔU = 0
    c, s = _synthetic(60, seed=3)
    field = GravityField(_dataset(c, s), 60)
    acc, grad = field.acceleration_and_gradient(POINTS_M)
    step_m = 10.0
    for k, pos in enumerate(POINTS_M):
        fd = np.stack([(field.acceleration(pos + step_m * e) - field.acceleration(pos - step_m * e))
                       / (2 * step_m) for e in np.eye(3)], axis=1)
        assert np.abs(grad[k] - fd).max() <= 1e-8 * np.linalg.norm(grad[k])
    np.testing.assert_array_equal(grad, np.swapaxes(grad, 1, 2))
    np.testing.assert_allclose(np.trace(grad, axis1=1, axis2=2), 0.0, atol=1e-14 * 3e-6)
    np.testing.assert_allclose(acc, field.acceleration(POINTS_M), rtol=0, atol=1e-15)


# ------------------------------------------------------------------------------ API


def test_shapes_and_kernel():
    c, s = _synthetic(10)
    field = GravityField(_dataset(c, s), 10)
    acc_one, grad_one = field.acceleration_and_gradient(POINTS_M[0])
    assert acc_one.shape == (3,) and grad_one.shape == (3, 3)
    assert field.acceleration(POINTS_M[0]).shape == (3,)
    assert field.acceleration(POINTS_M).shape == (5, 3)
    assert np.ndim(field.potential(POINTS_M[0])) == 0
    # authority: the same sums through the public jitted kernel (for use in jitted code)
    out = np.empty(3)
    field_sums(POINTS_M[0], *field.kernel_args("acceleration"), out)
    np.testing.assert_allclose(out, acc_one, rtol=0, atol=1e-15)
    acceleration_sums(POINTS_M[0], *field.kernel_args("acceleration"), out)
    np.testing.assert_allclose(out, acc_one, rtol=0, atol=1e-15)
    out = np.empty(9)
    field_sums(POINTS_M[0], *field.kernel_args("gradient"), out)
    np.testing.assert_array_equal(out[:3], acc_one)
    assert out[3:].tolist() == grad_one[np.triu_indices(3)].tolist()


def test_errors():
    c, s = _synthetic(10)
    with pytest.raises(ValueError, match="max_degree 11 outside 0..10"):
        GravityField(_dataset(c, s), 11)
    field = GravityField(_dataset(c, s), None)
    assert field.max_degree == 10 and field.tide_system == "zero_tide"
    with pytest.raises(ValueError, match="geocentre"):
        field.acceleration(np.zeros((2, 3)))
    with pytest.raises(ValueError, match="geocentre"):
        field.acceleration_and_gradient(np.zeros(3))


def test_decimal_year():
    # authority: definition (calendar arithmetic): 2004 has 366 days, 2005 has 365
    assert decimal_year("2005-01-01") == 2005.0
    assert decimal_year(np.datetime64("2004-07-02T00:00")) == 2004.5
    assert decimal_year("2005-07-02T12:00") == pytest.approx(2005 + 182.5 / 365, abs=1e-12)


def test_time_variable_synthetic():
    # authority: the ICGEM formula G(t) = G(t0) + trnd Δt + Σ acos cos(2πΔt/p) + asin sin(2πΔt/p)
    c, s = _synthetic(3)
    ds = _dataset(c, s, time_variable_terms="gfct trnd acos asin", t0="2005-01-01")
    trnd = np.zeros((4, 4))
    trnd[2, 0] = 1e-11
    amp = np.zeros((2, 4, 4))
    amp[0, 3, 1], amp[1, 3, 1] = 2e-11, 3e-11
    ds["trnd_C"], ds["trnd_S"] = (("n", "m"), trnd), (("n", "m"), trnd.T)
    ds = ds.assign_coords(period=("period", [1.0, 0.5]))
    ds["acos_C"] = ds["asin_S"] = (("period", "n", "m"), amp)
    ds["asin_C"] = ds["acos_S"] = (("period", "n", "m"), np.zeros_like(amp))
    field = GravityField(ds, 3, epoch_decimal_year=2007.25)
    dt = 2.25
    assert field.c[2, 0] == pytest.approx(c[2, 0] + 1e-11 * dt, abs=1e-20)
    # p = 1 year: cos(4.5π) = 0, sin(4.5π) = 1; p = 0.5 year: cos(9π) = −1, sin(9π) = 0
    assert field.c[3, 1] == pytest.approx(c[3, 1] - 3e-11, abs=1e-20)
    assert field.s[3, 1] == pytest.approx(s[3, 1] + 2e-11, abs=1e-20)
    # at t0 all cosines are 1: the gfct value plus the acos amplitudes
    c_t0, s_t0 = field.at_epoch(2005.0)
    assert c_t0[3, 1] == pytest.approx(c[3, 1] + 5e-11, abs=1e-20)
    np.testing.assert_array_equal(s_t0, s)
    # without an epoch: the static part (gfct) alone
    np.testing.assert_array_equal(GravityField(ds, 3).c, c)


# ------------------------------------------------------------------------- real models


@pytest.fixture(scope="module")
def egm2008(shared):
    return GravityField(read_icgem(shared / "models" / "gravity" / "EGM2008_120.gfc"))


def _unit_vectors(count: int) -> np.ndarray:
    u = np.random.default_rng(3).normal(size=(count, 3))
    return u / np.linalg.norm(u, axis=1)[:, None]


@pytest.mark.shared
def test_egm2008_vs_ggm05s(shared, egm2008):
    # authorities: EGM2008 and GGM05S are independent solutions (EGM2008 with terrestrial
    # data, GGM05S GRACE only): at 500 km they agree to ~1e-7 m/s², the difference being
    # dominated by their C̄20 (tide-free vs zero-tide, ΔC̄20 = 4.3e-9 -> ~1.6e-7 m/s²)
    ggm05s = GravityField(read_icgem(shared / "models" / "gravity" / "GGM05S.gfc",
                                     max_degree=120))
    assert (egm2008.tide_system, ggm05s.tide_system) == ("tide_free", "zero_tide")
    pos = _unit_vectors(500) * R_LEO_M
    acc = egm2008.acceleration(pos)
    assert np.all(np.abs(np.linalg.norm(acc, axis=1) - 8.42) < 0.02)  # GM/r² = 8.426 m/s²
    diff = np.linalg.norm(acc - ggm05s.acceleration(pos), axis=1)
    assert diff.max() < 5e-7
    # non-spherical part: J2 dominated, 1.5 J2 (R/r)² GM/r² ~ 1.2e-2 m/s² (analytic order)
    non_spherical = GravityField(read_icgem(shared / "models" / "gravity" / "EGM2008_120.gfc"),
                                 central_term=False).acceleration(pos)
    size = np.linalg.norm(non_spherical, axis=1)
    assert 8e-3 < size.min() and size.max() < 3e-2


@pytest.mark.shared
def test_egm2008_normal_gravity(egm2008):
    # authority: WGS 84 normal gravity on the ellipsoid (NIMA TR8350.2, eq. 4-1); EGM2008
    # gravity minus normal gravity is the gravity disturbance: area mean ~0, RMS ~30 mGal,
    # below ~200 mGal everywhere at degree 120; includes both poles (pole-safe recursion)
    lat = np.radians(np.linspace(-90.0, 90.0, 91))
    lon = np.radians(np.arange(0.0, 360.0, 4.0))
    lat, lon = (g.ravel() for g in np.meshgrid(lat, lon, indexing="ij"))
    e2 = (2 - 1 / WGS84_INV_F) / WGS84_INV_F
    prime = WGS84_A_M / np.sqrt(1 - e2 * np.sin(lat) ** 2)
    pos = np.stack([prime * np.cos(lat) * np.cos(lon), prime * np.cos(lat) * np.sin(lon),
                    prime * (1 - e2) * np.sin(lat)], axis=1)
    centrifugal = OMEGA_EARTH_WGS84_RAD_S ** 2 * pos * [1.0, 1.0, 0.0]
    gravity = np.linalg.norm(egm2008.acceleration(pos) + centrifugal, axis=1)
    normal = (WGS84_GAMMA_E_M_S2 * (1 + WGS84_K * np.sin(lat) ** 2)
              / np.sqrt(1 - WGS84_E2 * np.sin(lat) ** 2))
    disturbance = gravity - normal
    weight = np.cos(lat)
    assert abs(np.sum(disturbance * weight) / weight.sum()) < 1e-5  # 1 mGal
    assert np.sqrt(np.sum(disturbance ** 2 * weight) / weight.sum()) < 5e-4
    assert np.abs(disturbance).max() < 3e-3


@pytest.mark.shared
def test_eigen6s_degree_240_epoch_and_pole(shared):
    # authority: ICGEM formula with the records of eigen-6s.gfc lines 79-84 (C̄20: gfct,
    # trnd, acos/asin with p = 1 and 0.5 year, t0 = 2005-01-01); one year after t0 all
    # cosines are 1 and sines 0
    ds = read_icgem(shared / "models" / "gravity" / "eigen-6s.gfc")
    field = GravityField(ds, 240, epoch_decimal_year=2006.0)
    expected = (-4.84165299820e-04 - 1.26059939709e-11 + 4.10019292536e-11 + 3.33920225943e-11)
    assert field.c[2, 0] == pytest.approx(expected, abs=1e-22)
    assert field.tide_system == "tide_free"
    # near the pole at degree 240: the acceleration at two points 1e-6 rad (7 m) on either
    # side of the axis differs by the gradient on the axis times their separation (authority:
    # Taylor's theorem; the symmetric difference has no second-order term, the third-order
    # one is ~ GM/r⁵ (7 m)³ ~ 1e-18 m/s²; tolerance: round-off of two sums of |a| = 8.4 m/s²)
    on_axis = np.array([0.0, 0.0, R_LEO_M])
    sides = np.stack([_sph(R_LEO_M, 1e-6, 0.7), _sph(R_LEO_M, 1e-6, 0.7 + np.pi)])
    acc, grad = field.acceleration_and_gradient(np.vstack([on_axis, sides]))
    assert np.isfinite(grad).all()
    np.testing.assert_allclose(acc[1] - acc[2], grad[0] @ (sides[0] - sides[1]), rtol=0,
                               atol=5e-14)
