"""Values of Gilabert, Roux & Castellanos 2007 ("[GRC]", /work/shared/papers/gilabert-roux-
castellanos-2007-cohesive-powders.md), as printed, for jobs/tools/case_table.py --against.

Tables II (method 1 without cohesion, P/K_N = 1e-5) and III (method 1 with cohesion, P* =
0.01): Phi and z per case, keyed as jobs/runs/method1_sweep.sh names its cases,
"PHI_I-MU-norr|rr". Each value is (mean, sd): the sd is [GRC]'s "standard deviation" over
samples whose number they do not state. z is their z: force-carrying contacts without cohesion
(report.json "z"), every interaction with it, distant attractions included
("values.z_interactions").
"""

# Columns of both tables: (mu 0.15, no RR), (mu 0.5, no RR), (mu 0.15, RR), (mu 0.5, RR).
_COLUMNS = ("0.15-norr", "0.5-norr", "0.15-rr", "0.5-rr")
_ROWS = ("0.13", "0.36", "0.52")  # Phi_I (printed: 0.130, 0.3631, 0.5244)

_TABLE_II_PHI = (
    ((0.8262, 0.0007), (0.811, 0.001), (0.8238, 0.0014), (0.803, 0.002)),
    ((0.8256, 0.0005), (0.811, 0.001), (0.8231, 0.0013), (0.805, 0.002)),
    ((0.8236, 0.0007), (0.8092, 0.0005), (0.8215, 0.0005), (0.803, 0.011)),
)
_TABLE_II_Z = (
    ((3.174, 0.012), (2.607, 0.022), (3.160, 0.024), (2.526, 0.021)),
    ((3.187, 0.025), (2.65, 0.02), (3.123, 0.013), (2.475, 0.025)),
    ((3.181, 0.015), (2.63, 0.02), (3.15, 0.03), (2.52, 0.02)),
)
_TABLE_III_PHI = (
    ((0.7635, 0.0023), (0.751, 0.001), (0.757, 0.002), (0.709, 0.001)),
    ((0.727, 0.001), (0.7232, 0.0012), (0.710, 0.002), (0.688, 0.001)),
    ((0.737, 0.002), (0.733, 0.002), (0.7248, 0.0002), (0.733, 0.002)),
)
_TABLE_III_Z = (
    ((3.563, 0.005), (3.163, 0.004), (3.189, 0.008), (3.059, 0.003)),
    ((3.345, 0.009), (3.103, 0.006), (3.253, 0.003), (2.971, 0.006)),
    ((3.189, 0.008), (3.059, 0.003), (3.096, 0.002), (2.851, 0.001)),
)


def _by_case(phi, z):
    table = {}
    for r, row in enumerate(_ROWS):
        for c, col in enumerate(_COLUMNS):
            table[f"{row}-{col}"] = {"phi": phi[r][c], "z": z[r][c]}
    return table


# TABLES["II"]["0.36-0.5-norr"] == {"phi": (0.811, 0.001), "z": (2.65, 0.02)}
TABLES = {"II": _by_case(_TABLE_II_PHI, _TABLE_II_Z),
          "III": _by_case(_TABLE_III_PHI, _TABLE_III_Z)}
# Cells whose printed value is probably not the measurement, with the evidence. case_table.py
# marks them and counts the agreement with and without them.
_ROW_013_RR_REPEATS = ("table III's row Phi_I = 0.130 with RR (3.189 +- 0.008, 3.059 +- 0.003) "
                      "repeats row 0.5244 without RR, value and sd alike: probably a copying "
                      "error in [GRC]")
SUSPECT = {
    "III": {("0.13-0.15-rr", "z"): _ROW_013_RR_REPEATS, ("0.13-0.5-rr", "z"): _ROW_013_RR_REPEATS},
}
# Which report value is [GRC]'s z in each table.
Z_KEY = {"II": "z", "III": "z_int"}
