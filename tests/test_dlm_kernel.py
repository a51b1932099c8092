"""wingmdao.aero.dlm_kernel (the doublet lattice's oscillatory AIC, all k in one call) against
PanelAero's ``DLM.calc_Ajj(method="quartic")`` (A. Voss, DLR, https://github.com/DLR-AE/PanelAero),
evaluated per k on the same panels; and the pressure operators of wingmdao.aero.dlm (symmetric
AIC of the right half's rows) against PanelAero's whole wing (both halves, VLM + DLM, inverted).
Skipped without the ``aero3d`` extra."""

import numpy as np
import pytest

from wingmdao.aero import dlm
from wingmdao.aero.dlm_kernel import oscillatory_aic
from wingmdao.aero.vlm import build_lattice, flat_wing

panelaero_dlm = pytest.importorskip("panelaero.DLM")
panelaero_vlm = pytest.importorskip("panelaero.VLM")


def _two_surfaces():
    """A swept, tapered wing with dihedral (both halves) and a smaller surface 0.15 m above it with
    other strip edges: coplanar pairs, and nonplanar ones in every branch of the kernel's
    quadrature (near and far, inside and outside the sending line's circle)."""
    r, c, ref = flat_wing(6.0, lambda y: 2.0 - 0.12 * y, sweep_quarter_deg=25.0, n_stations=7, ref_point=0.4)
    r[:, 2] = 0.05 * r[:, 1]
    wing = dlm.aerogrid(build_lattice(r, c, ref, mach=0.3, n_chordwise=3, n_spanwise=2))
    r2, c2, ref2 = flat_wing(4.0, lambda y: np.full_like(y, 1.2), n_stations=6, ref_point=0.25, spacing="uniform")
    tail = dlm.aerogrid(build_lattice(r2 + np.array([0.5, 0.0, 0.15]), c2, ref2, mach=0.3, n_chordwise=2,
                                      n_spanwise=3))
    return {key: wing[key] + tail[key] if key == "n" else np.concatenate([wing[key], tail[key]]) for key in wing}


def _branches(grid):
    """Pair counts of the kernel's branches (Rodden, Taylor & McIntosh 1998, eqs. 22-34)."""
    mid = 0.5 * (grid["offset_P1"] + grid["offset_P3"])
    d = grid["offset_P3"] - grid["offset_P1"]
    e = 0.5 * np.hypot(d[:, 1], d[:, 2])
    sin_g, cos_g = d[:, 2] / (2 * e), d[:, 1] / (2 * e)
    ysr = grid["offset_j"][:, 1, None] - mid[None, :, 1]
    zsr = grid["offset_j"][:, 2, None] - mid[None, :, 2]
    y, z = ysr * cos_g + zsr * sin_g, zsr * cos_g - ysr * sin_g
    q = y ** 2 + z ** 2 - e ** 2
    ratio = np.abs(2 * e * np.abs(z)) / np.abs(q)
    nonplanar = np.abs(z) / e > 0.001
    return {"coplanar": np.sum(~nonplanar), "near": np.sum(nonplanar & (ratio >= 10.0)),
            "far": np.sum(nonplanar & (ratio < 10.0)), "series": np.sum(nonplanar & (ratio <= 0.3)),
            "inside": np.sum(nonplanar & (q < 0.0))}


@pytest.mark.parametrize("mach", [0.0, 0.3, 0.8])
def test_oscillatory_aic_equals_panelaero(mach):
    """All k of one call equal PanelAero's per-k AIC to round-off (1e-12 of the largest entry;
    measured 2e-14); the rows option gives those rows; k = 0 no increment."""
    grid = _two_surfaces()
    assert all(v > 0 for v in _branches(grid).values()), _branches(grid)
    ks = np.array([0.0, 0.05, 0.8, 2.5])
    A = oscillatory_aic(grid["offset_j"], grid["offset_P1"], grid["offset_P3"], grid["l"], mach, ks)
    assert np.all(A[0] == 0.0)
    for i, k in enumerate(ks[1:], start=1):
        with np.errstate(all="ignore"):
            ref = panelaero_dlm.calc_Ajj(aerogrid={key: np.copy(v) for key, v in grid.items()}, Ma=mach, k=k,
                                         method="quartic")
        assert np.all(np.isfinite(A[i]))
        assert np.abs(A[i] - ref).max() <= 1e-12 * np.abs(ref).max(), (k, np.abs(A[i] - ref).max() / np.abs(ref).max())
    rows = np.array([3, 40, 7, 100])
    sub = oscillatory_aic(grid["offset_j"], grid["offset_P1"], grid["offset_P3"], grid["l"], mach, ks[1:], rows=rows)
    np.testing.assert_allclose(sub, A[1:, rows], rtol=1e-14, atol=1e-14 * np.abs(A).max())


@pytest.mark.parametrize("mach, dihedral_deg", [(0.0, 0.0), (0.6, 6.0)])
def test_pressure_operators_equal_panelaero_whole_wing(mach, dihedral_deg):
    """The right half's pressure operators -(A_RR + A_RL)^-1 (oscillatory kernel of the right
    half's rows only) equal the whole wing's -(A^-1)_RR - (A^-1)_RL with PanelAero's VLM + DLM
    AIC of both halves, to 1e-10 of the largest entry."""
    r, c, ref = flat_wing(6.0, lambda y: 2.0 - 0.12 * y, sweep_quarter_deg=25.0, n_stations=7, ref_point=0.4)
    r[:, 2] = np.tan(np.radians(dihedral_deg)) * r[:, 1]
    lat = build_lattice(r, c, ref, mach=mach, n_chordwise=3, n_spanwise=2)
    kb = np.array([0.0, 0.1, 0.6])
    D = dlm.pressure_operators(lat, kb)
    m = lat.span.size
    A0, _ = panelaero_vlm.calc_Ajj(aerogrid=dlm.aerogrid(lat), Ma=mach)
    for i, k in enumerate(kb):
        A = A0.astype(complex)
        if k > 0.0:
            with np.errstate(all="ignore"):
                A = A + panelaero_dlm.calc_Ajj(aerogrid=dlm.aerogrid(lat), Ma=mach, k=k, method="quartic")
        inv = np.linalg.inv(A)[:m]
        expected = -(inv[:, :m] + inv[:, m:])
        assert np.abs(D[i] - expected).max() <= 1e-10 * np.abs(expected).max()
