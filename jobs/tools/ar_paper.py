"""Values of Agnolin & Roux 2007, paper I ("[AR]", /work/shared/papers/agnolin-roux-2007-
isotropic-packings-I.md), as printed, for jobs/tools/ar_tables.py.

Every value is the paper's text, kept as a string so that its printed precision survives
("0.6370", "4.0"): "v", "v ± s" (s: one sample-to-sample standard deviation over [AR]'s 5
samples, sec. III A), "(v ± s) × 10^e", "~v" or "≃ v" (approximate, no sd), "< v" (an upper
bound), and None where the paper gives no value ("n. d." or a blank). parse() turns one into
numbers. Units are the paper's: x_i, x0, x2 and the windows of tables VII-VIII in %.
Where the paper gives two different numbers for one quantity, the table's is used and the
other is quoted in a comment ("also:").
"""
import re

# Table I: x_i (%) of grains with i contacts, i = 0..11, in A and A' at kappa = 39000;
# (I) ignoring contacts with or between rattlers, (II) rattlers fixed onto the backbone.
TABLE_I = {
    "A (I)": ("1.3", "0", "0", "0", "11.1", "23.2", "28.4", "22.6", "10.3", "2.8", "0.3", "0.02"),
    "A' (I)": ("1.8", "0", "0", "0", "11.6", "22.5", "28.2", "22.3", "10.6", "2.8", "0.3", "0.01"),
    "A (II)": ("0", "0", "0", "1.1", "10.7", "22.7", "28.2", "22.9", "10.9", "3.1", "0.3", "0.02"),
    "A' (II)": ("0", "0", "0", "1.7", "10.9", "21.9", "28.2", "22.5", "11.4", "3.1", "0.3", "0.01"),
}

# Table II: bond-order indicators of A and A' at kappa = 39000, bonds shorter than d_c.
# Columns: Z, Z_cr, Q6 (global), Q6^loc, Q6^loc,cr, x_cr, <n_cr> (the last has no sd).
TABLE_II_COLUMNS = ("Z", "Z_cr", "Q6", "Q6loc", "Q6loc_cr", "x_cr", "<n_cr>")
TABLE_II = {
    ("A", "1.35"): ("12.36 ± 0.03", "2.91 ± 0.06", "(1.7 ± 0.3) × 10^-2", "0.392 ± 0.001",
                    "0.417 ± 0.003", "0.080 ± 0.005", "19.8"),
    ("A'", "1.35"): ("12.50 ± 0.02", "3.13 ± 0.11", "(1.9 ± 0.5) × 10^-2", "0.398 ± 0.0005",
                     "0.420 ± 0.002", "0.104 ± 0.006", "54.8"),
    ("A", "1.40"): ("13.11 ± 0.02", "2.94 ± 0.06", "(1.6 ± 0.3) × 10^-2", "0.370 ± 0.001",
                    "0.394 ± 0.002", "0.083 ± 0.006", "22.8"),
    ("A'", "1.40"): ("13.20 ± 0.02", "3.16 ± 0.11", "(1.8 ± 0.3) × 10^-2", "0.377 ± 0.0006",
                     "0.397 ± 0.003", "0.103 ± 0.006", "64.5"),
}

# Columns of tables III and IV: Phi, z*, x0 (%), x2 (%), Z(2), M1, M2; table IV printed by
# ar_tables.py adds H/N_f* of sec. IV E-F.
STATE_COLUMNS = ("Φ", "z*", "x0", "x2", "Z(2)", "M1", "M2")

# Table III: D-type states. Keys are the state names ar_tables.py expects on the command line;
# "conditions" are the paper's Origin, P (kPa), zeta, I_max columns.
TABLE_III = {
    "D": {"conditions": ("gas", "1", "0.98", "10^-3"),
          "values": ("0.5930 ± 0.0007", "4.546 ± 0.009", "11.1 ± 0.4", "2.39", "1.58", "0.160",
                     "0.217")},  # also: table IV and sec. IV A give Phi = 0.5923 ± 0.0006
    "D_10kPa": {"conditions": ("gas", "10", "0.98", "10^-3"),
                "values": ("0.5946 ± 0.0006", "4.59 ± 0.02", "10.2 ± 0.2", "2.07", "1.59",
                           "0.159", "0.213")},
    "D_zeta0.098": {"conditions": ("gas", "10", "0.098", "10^-3"),
                    "values": ("0.5938 ± 0.0008", "4.61 ± 0.02", "10.9 ± 0.2", "1.79", "1.57",
                               "0.150", "0.194")},
    "D_I0.1": {"conditions": ("gas", "10", "0.98", "10^-1"),
               "values": ("0.5931 ± 0.0002", "4.60 ± 0.01", "10.2 ± 0.7", "1.80", "1.59", "0.159",
                          "0.212")},
    "D_QS_10kPa": {"conditions": ("QS", "10", "0.98", "10^-3"),
                   "values": ("0.5931 ± 0.0006", "4.641 ± 0.011", "10.1 ± 0.4", "2.33", "1.46",
                              "0.146", "0.188")},
    "D_100kPa": {"conditions": ("gas", "100", "0.98", "10^-3"),
                 "values": ("0.5975 ± 0.001", "4.69 ± 0.02", "8.9 ± 0.5", "1.66", "1.61", "0.153",
                            "0.197")},
    "D_QS_100kPa": {"conditions": ("QS", "100", "0.98", "10^-3"),
                    "values": ("0.5936 ± 0.0006", "4.79 ± 0.02", "8.6 ± 0.4", "2.05", "1.40",
                               "0.138", "0.178")},
}

# Table IV (A, B, C, D) completed from the text for A' and Z, plus H/N_f* (the degree of
# hyperstaticity per backbone degree of freedom, eq. 37) of sec. IV E-F. Each value is
# (text, source); TABLE_IV_COLUMNS is STATE_COLUMNS + H/N_f*.
TABLE_IV_COLUMNS = STATE_COLUMNS + ("H/N_f*",)
_T4 = "[AR] table IV"
TABLE_IV = {
    "A": {"Φ": ("0.6370 ± 0.0002", _T4),  # also: sec. III A, "Phi = 0.6370 ± 0.0015"
          "z*": ("6.074 ± 0.0015", _T4),  # also: sec. III B, "z* = 6.074 ± 0.002"
          "x0": ("1.3 ± 0.2", _T4),       # sec. III B: x0 = 0.013 ± 0.002 (same)
          "x2": ("0", _T4), "Z(2)": ("1.53", _T4), "M1": ("0", _T4), "M2": ("0", _T4)},
    # A': sec. III A ("Phi = 0.6422 ± 0.0002", fig. 1); x0 and x2 from table I, row A' (I)
    # (sec. III C: "x0 ≃ 1.8%"). z*, Z(2), M1, M2 are not given.
    "A'": {"Φ": ("0.6422 ± 0.0002", "[AR] sec. III A"),
           "x0": ("1.8", "[AR] table I"), "x2": ("0", "[AR] table I")},
    # B: table IV, "B (mu_0 = 0.02)". Also: sec. IV A 2 gives "Phi = 0.627 ± 2.10^-4",
    # "z* = 5.75 ± 8.10^-3" and "x0 = (1.95 ± 0.02)%" for the same state.
    "B": {"Φ": ("0.6271 ± 0.0002", _T4), "z*": ("5.80 ± 0.007", _T4), "x0": ("1.95 ± 0.02", _T4),
          "x2": ("~10^-4", _T4), "Z(2)": ("1.52", _T4), "M1": ("0.016", _T4),
          "M2": ("0.018", _T4)},
    # C: table IV, "C (lambda = 1.005)"; H/N_f* from sec. IV F ("0.141 in D samples and 0.145
    # in C ones").
    "C": {"Φ": ("0.635 ± 0.002", _T4), "z*": ("4.56 ± 0.03", _T4), "x0": ("13.3 ± 0.5", _T4),
          "x2": ("2.64", _T4), "Z(2)": ("1.65", _T4), "M1": ("0.135", _T4), "M2": ("0.181", _T4),
          "H/N_f*": ("0.145", "[AR] sec. IV F")},
    "D": {"Φ": ("0.5923 ± 0.0006", _T4), "z*": ("4.546 ± 0.009", _T4), "x0": ("11.1 ± 0.4", _T4),
          "x2": ("2.39", _T4), "Z(2)": ("1.58", _T4), "M1": ("0.160", _T4), "M2": ("0.217", _T4),
          "H/N_f*": ("0.141", "[AR] sec. IV F")},
    # Z (mu = infinity): sec. IV E; "H/N_f ≃ 0.031" is per backbone degree of freedom (eq. 37
    # with its z*, x0, x2 gives 0.0309), like sec. IV F's values.
    "Z": {"Φ": ("0.5917 ± 0.0008", "[AR] sec. IV E"), "z*": ("4.068 ± 0.006", "[AR] sec. IV E"),
          "x0": ("18.4 ± 0.5", "[AR] sec. IV E"), "x2": ("6.8 ± 0.5", "[AR] sec. IV E"),
          "H/N_f*": ("≃ 0.031", "[AR] sec. IV E")},
}

# Table V: x_i (%), i = 0..10, of B, C, D; (I) ignoring contacts with or between rattlers,
# (II) rattlers fixed onto the backbone.
TABLE_V = {
    "B (I)": ("1.95", "0", "0.05", "0.5", "16.3", "26.9", "27.5", "18.4", "7.1", "1.4", "0.1"),
    "C (I)": ("13.3", "0", "2.6", "15.1", "26.5", "23.4", "13.2", "4.8", "0.9", "0.15", "0"),
    "D (I)": ("11.1", "0", "2.4", "13.8", "29.1", "25.6", "13.3", "4.0", "0.7", "0.03", "0"),
    "B (II)": ("0", "0", "0", "2.1", "15.3", "26.5", "27.5", "18.9", "7.8", "1.6", "0.2"),
    "C (II)": ("0", "0", "0", "18.9", "22.8", "27.0", "18.6", "9.3", "2.8", "0.5", "0.1"),
    "D (II)": ("0", "0", "0", "17.2", "25.4", "29.0", "18.5", "7.7", "1.9", "0.3", "0"),
}

# Table VI: X1, M1, M2 of all backbone contacts, then N, X1, M1, M2 of the contacts of 2- and
# of 3-coordinated grains (N in units of P a^2). B has no divalent grain: "n. d.".
TABLE_VI_COLUMNS = ("X1", "M1", "M2", "N(2)", "X1(2)", "M1(2)", "M2(2)", "N(3)", "X1(3)",
                    "M1(3)", "M2(3)")
TABLE_VI = {
    "B": ("0.42", "0.016", "0.018", None, None, None, None, "0.23", "0.09", "0.02", "0.01"),
    "C": ("0.41", "0.14", "0.18", "0.58", "0.19", "0.14", "0.17", "0.24", "0.09", "0.13", "0.04"),
    "D": ("0.41", "0.16", "0.22", "0.71", "0.22", "0.16", "0.18", "0.26", "0.10", "0.15", "0.05"),
}

# Tables VII (A, A', C against Aste et al.'s dense sample F) and VIII (B against sample D,
# D against sample B): % of grains in the dis, fcc and hcp windows of (Q4, Q6), d_c in a.
# Only [AR]'s simulated rows; the experimental rows are not compared.
ORDER_COLUMNS = ("dis", "fcc", "hcp")
TABLE_VII = {
    "A": {"1.1": ("32", "< 10^-2", "4"), "1.2": ("37", "< 10^-2", "5"),
          "1.3": ("43", "< 10^-2", "8"), "1.4": ("46", "< 10^-2", "12")},
    "A'": {"1.1": ("31", "< 10^-2", "5"), "1.2": ("40", "< 10^-2", "6"),
           "1.3": ("45", "< 10^-2", "10"), "1.4": ("48", "< 10^-2", "15")},
    "C": {"1.1": ("31", "< 10^-2", "4"), "1.2": ("37", "< 10^-2", "5"),
          "1.3": ("43", "< 10^-2", "8"), "1.4": ("46", "< 10^-2", "13")},
}
TABLE_VIII = {
    "B": {"1.1": ("30", "< 10^-2", "2.7"), "1.2": ("38", "< 10^-2", "7.6"),
          "1.3": ("43", "< 10^-2", "10"), "1.4": ("46", "< 10^-2", "10")},
    "D": {"1.1": ("24", "< 10^-2", "1.0"), "1.2": ("32", "< 10^-2", "4.4"),
          "1.3": ("37", "< 10^-2", "6.1"), "1.4": ("43", "< 10^-2", "7.5")},
}
# The experimental sample (granpack analyze's `windows` key) each simulated state is set against.
ORDER_WINDOW = {"A": "aste_F", "A'": "aste_F", "C": "aste_F", "B": "aste_D", "D": "aste_B"}

# Fig. 1: the points whose values the text gives (sec. III A): A at n = 4000 ("Phi = 0.6370 ±
# 0.0015", the error bar drawn; table IV prints ± 0.0002) and A' at n = 4000. The n = 1372
# point and OSLN's band are drawn but not given as numbers.
FIG_1 = {"A": ("4000", "0.6370 ± 0.0015"), "A'": ("4000", "0.6422 ± 0.0002")}
# Fig. 4 caption: the DTS fit P(f) = (3.43 f^2 + 1.45 - 1.18/(1 + 4.71 f)) exp(-2.25 f).
DTS_FIT = {"a": "3.43", "b": "1.45", "c": "1.18", "d": "4.71", "e": "2.25"}
# Figs. 10-12 captions: slopes beta_II, beta_I of the dotted power-law fits of eq. (35).
FIG_ZH = {"D": {"figure": "10", "beta_II": "0.51", "beta_I": "0.35"},
          "B": {"figure": "11", "beta_II": "0.56", "beta_I": "0.45"},
          "C": {"figure": "12", "beta_II": "0.6", "beta_I": "0.37"}}

_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
_POWER = r"10\^(-?\d+)"


def _number(text):
    """A decimal or 10^e, as float."""
    m = re.fullmatch(_POWER, text)
    return 10.0 ** int(m.group(1)) if m else float(text)


def decimals(text):
    """Digits after the decimal point that the printed value carries (10^-e counts e)."""
    m = re.search(r"×\s*10\^(-?\d+)", text)
    exp = int(m.group(1)) if m else 0
    core = re.sub(r"\s*×\s*10\^-?\d+", "", text)
    first = re.search(_POWER + "|" + _NUMBER, core.lstrip("(~≃< "))
    if first is None:
        return 0
    token = first.group(0)
    if token.startswith("10^"):
        return max(0, -int(token[3:]))
    return max(0, (len(token.split(".")[1]) if "." in token else 0) - exp)


def parse(text):
    """A paper cell as dict(value, sd, kind) with kind "value", "approx" or "bound"
    (value is then the upper bound); None for no value."""
    if text is None:
        return None
    t = text.strip()
    kind = "value"
    if t[:1] in "~≃":
        kind, t = "approx", t[1:].strip()
    elif t[:1] == "<":
        kind, t = "bound", t[1:].strip()
    scale = 1.0
    m = re.fullmatch(r"\((.*)\)\s*×\s*" + _POWER, t)
    if m:
        t, scale = m.group(1), 10.0 ** int(m.group(2))
    parts = [p.strip() for p in t.split("±")]
    if len(parts) > 2:
        raise ValueError(f"cannot parse paper value {text!r}")
    value = _number(parts[0]) * scale
    sd = _number(parts[1]) * scale if len(parts) == 2 else None
    return {"value": value, "sd": sd, "kind": kind, "text": text,
            "rounding": rounding(value, text, kind)}


def rounding(value, text, kind):
    """Half-width of what a printed value without "±" can stand for: half a unit of its last
    digit (1.53 is 1.525-1.535); "~v" only its order, so v itself; an exact 0 (a frictionless
    M1, x2 = 0 without friction) nothing."""
    if kind == "approx":
        return abs(value)
    if value == 0:
        return 0.0
    return 0.5 * 10.0 ** (-decimals(text))
