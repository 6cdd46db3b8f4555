"""Single-receiver integer ambiguity resolution of LEO onboard GNSS phase (Peng et al. 2021;
Jiang et al. 2023; BDS SCB-AR paper).

Chain (one GNSS system and one frequency pair at a time):

1. :func:`pairs.sd_pairs` — single-difference pairs of passes of different satellites with
   at least 8 minutes of common observation time (Peng et al. 2021);
2. :func:`wide_lane.sd_wide_lane` — float SD wide-lane ambiguities from the HMW
   combination over the common epochs, corrected by the satellite WL biases of the
   products (:func:`wide_lane.sat_wl_bias_cnes`, :func:`wide_lane.sat_wl_bias_osb`);
3. :func:`decision.rounding_decision` / :func:`decision.dong_bock_decision` — WL fixing;
4. :func:`narrow_lane.sd_narrow_lane` — float SD narrow-lane ambiguities from the float
   IF ambiguities of the POD and the fixed WL, then NL fixing (3.);
5. :func:`narrow_lane.fixed_sd_if_m` and :func:`independent.constraint_rows` — fixed SD IF
   ambiguities of a maximal independent set as pseudo-observations for the fixed POD;
   :func:`independent.fixing_rate` — WL and NL fixing rates (Jiang et al. 2023).

Between two LEOs of a formation, :mod:`double_difference` resolves inter-satellite double
differences (no bias product needed) with the same pieces: :func:`double_difference.resolve_dd`.

Sign conventions of the bias products: docstrings of :mod:`leopod.ambiguity.wide_lane` and
:mod:`leopod.simulate.biases`.
"""

from leopod.ambiguity.decision import (
    BootstrapResult,
    FixDecision,
    dong_bock_decision,
    dong_bock_probability,
    integer_bootstrap,
    rounding_decision,
)
from leopod.ambiguity.independent import (
    ConstraintRows,
    constraint_matrix,
    constraint_rows,
    fixing_rate,
    graph_rank,
    independent_edges,
)
from leopod.ambiguity.narrow_lane import (
    SdNarrowLane,
    fixed_sd_if_m,
    sat_if_phase_bias_osb,
    sd_covariance_m2,
    sd_narrow_lane,
)
from leopod.ambiguity.pairs import SdPairs, sd_pairs
from leopod.ambiguity.wide_lane import (
    SdWideLane,
    hmw_cycles,
    pass_hmw,
    sat_osb_m,
    sat_wl_bias_cnes,
    sat_wl_bias_osb,
    sd_wide_lane,
)

__all__ = [
    "BootstrapResult", "ConstraintRows", "FixDecision", "SdNarrowLane", "SdPairs",
    "SdWideLane", "constraint_matrix", "constraint_rows", "dong_bock_decision",
    "dong_bock_probability", "fixed_sd_if_m", "fixing_rate", "graph_rank", "hmw_cycles",
    "independent_edges", "integer_bootstrap", "pass_hmw", "rounding_decision",
    "sat_if_phase_bias_osb", "sat_osb_m", "sat_wl_bias_cnes", "sat_wl_bias_osb",
    "sd_covariance_m2", "sd_narrow_lane", "sd_pairs", "sd_wide_lane",
]
