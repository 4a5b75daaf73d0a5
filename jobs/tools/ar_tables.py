#!/usr/bin/python3
"""Tables and figures of [AR] (Agnolin & Roux 2007, paper I) from granpack ensemble files.

Usage:
  ar_tables.py --state STATE=FILE:STEM [--state ...] [--tables I,II,III,IV,V,VI,VII,VIII]
               [--figures DIR] [--fig2 [LABEL=]FILE:STEM ...] [--check TOLERANCES.md]

FILE is an ensemble.json written by `granpack ensemble`, STEM the configuration whose
analysis gives the state (`out/C/ensemble.json:A`). Several FILEs may be given for one state
(fig. 1 draws them all; the tables use the one with n = 4000, [AR]'s size, else the first).
STATE names: A, A', B, C, D, Z (tables I-VIII), A(II), B(II), ... for treatment II (rattlers
fixed onto the backbone: tables I, V and figs. 10-12), and D_10kPa, D_100kPa, D_QS_10kPa,
D_QS_100kPa, D_zeta0.098, D_I0.1 for the rows of table III.

Every cell is printed as our mean ± sample standard deviation over the K finished samples,
[AR]'s value ± theirs (5 samples), and dev = (ours − paper) / sqrt(sd² / K + sd_paper² / 5).
--check reads the tolerances of table IV from the Markdown table under the heading
"### Table IV tolerances (checked by CI)" and exits 1 if any |dev| exceeds its tolerance.
Exit codes: 0 fine, 1 a tolerance exceeded (--check), 2 bad input. See docs/ar-tables.md.
"""
import argparse
import json
import math
import re
import sys
from collections import namedtuple
from pathlib import Path

import ar_paper as paper
import granpack_io as gio

PROG = "ar_tables.py"
PAPER_SAMPLES = 5  # [AR] sec. III: "five different configurations of n = 4000 beads"
PAPER_N = 4000
FIT_H_MIN, FIT_H_MAX = 1e-4, 0.04  # window of granpack analyze's eq. (35) fit (docs/analysis.md)
TOLERANCE_HEADING = "### Table IV tolerances (checked by CI)"
TOLERANCE_COLUMNS = ("state", "quantity", "tolerance (combined standard errors)", "why")
ALL_TABLES = ("I", "II", "III", "IV", "V", "VI", "VII", "VIII")
TABLE_III_STATES = tuple(paper.TABLE_III)

# grains, scale: for a fraction of grains (x0, x2, x_i), the grains per sample and the factor
# that took the fraction to the printed unit (100 for %); None otherwise.
Stat = namedtuple("Stat", "mean sd K grains scale", defaults=(None, 1.0))
Source = namedtuple("Source", "state path stem ensemble")
# One quantity of a table: label, JSON pointer in the analysis, factor to the paper's unit,
# whether a missing key means 0 (x_i lists only the occupied classes), and whether it is a
# fraction of grains (a count, with a binomial error: see deviation()).
Quantity = namedtuple("Quantity", "label pointer scale zero_if_absent grain_fraction",
                      defaults=(False,))
# One printed row group: label, states it needs, per-column quantities and paper texts.
RowSpec = namedtuple("RowSpec", "label state quantities paper note")


class InputError(Exception):
    """Bad input: a message naming the file, key or line, and exit code 2."""


def note(msg):
    print(f"{PROG}: {msg}", file=sys.stderr)


# ---------------------------------------------------------------- ensemble files

def load_ensemble(path):
    """The ensemble.json (granpack_io.read_ensemble), checked for the keys this tool relies on."""
    try:
        data = gio.read_ensemble(path)
    except gio.GranpackFileError as e:
        raise InputError(str(e)) from None
    version = data.get("format_version")
    if not isinstance(version, int) or version < 1:
        raise InputError(f"{path}: \"format_version\" must be an integer >= 1, got {version!r}")
    if version > 1:
        note(f"{path}: format_version {version} is newer than this tool (1); reading on")
    for key in ("report", "analysis"):
        if not isinstance(data.get(key), dict):
            raise InputError(f"{path}: no \"{key}\" object")
    return data


def parse_source(text, cache):
    """STATE=FILE:STEM as a Source (FILE read once per path)."""
    state, sep, rest = text.partition("=")
    path, sep2, stem = rest.rpartition(":")
    if not sep or not sep2 or not state.strip() or not path or not stem:
        raise InputError(f"--state {text!r}: expected STATE=FILE:STEM, e.g. "
                         "A=out/C/ensemble.json:A")
    state = normal_state(state)
    if path not in cache:
        cache[path] = load_ensemble(path)
    ens = cache[path]
    if stem not in ens["analysis"]:
        have = ", ".join(sorted(ens["analysis"])) or "none"
        raise InputError(f"{path}: no analysis of configuration {stem!r} (state {state}); "
                         f"the file has: {have}")
    return Source(state, path, stem, ens)


def normal_state(name):
    """State names without blanks, so "A (II)" and "A(II)" are the same."""
    return re.sub(r"\s+", "", name)


def ensemble_n(ens):
    """n of the samples: the reports' /n, else the ensemble's top-level "n"."""
    s = ens["report"].get("/n")
    if isinstance(s, dict) and isinstance(s.get("mean"), (int, float)):
        return int(round(s["mean"]))
    n = ens.get("n")
    return int(n) if isinstance(n, (int, float)) else None


def table_source(sources):
    """The file the tables use when a state has several: n = 4000 ([AR]'s size), else first."""
    for s in sources:
        if ensemble_n(s.ensemble) == PAPER_N:
            return s
    return sources[0]


def mean_sd(values):
    """Mean and sample standard deviation (K − 1 denominator; None for one value)."""
    k = len(values)
    if k == 0:
        return Stat(None, None, 0)
    m = sum(values) / k
    sd = math.sqrt(sum((v - m) ** 2 for v in values) / (k - 1)) if k > 1 else None
    return Stat(m, sd, k)


def checked_stat(raw, where):
    """A scalar STAT as Stat, or InputError naming the file and key."""
    if not isinstance(raw, dict) or "mean" not in raw or "K" not in raw:
        raise InputError(f"{where}: not a statistic (needs \"mean\", \"sd\", \"K\")")
    mean, sd, k = raw["mean"], raw.get("sd"), raw["K"]
    if mean is None:
        return None
    if not all(is_number(v) for v in (mean, k)) or not (sd is None or is_number(sd)):
        raise InputError(f"{where}: \"mean\", \"K\" must be numbers and \"sd\" a number or "
                         f"null (a scalar statistic), found {json.dumps(raw)[:120]}")
    return Stat(float(mean), None if sd is None else float(sd), int(k))


def is_number(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def present_seeds(src):
    """Per seed, whether the stem's analysis exists (its /n or /phi has a value)."""
    block = src.ensemble["analysis"][src.stem]
    for ref in ("/n", "/phi"):
        values = block.get(ref, {}).get("values") if isinstance(block.get(ref), dict) else None
        if isinstance(values, list):
            return [v is not None for v in values]
    return None


def stat(src, pointer, zero_if_absent=False):
    """Stat of one analysis key of the source's stem, None if absent."""
    block = src.ensemble["analysis"][src.stem]
    raw = block.get(pointer)
    where = f"{src.path}: analysis {src.stem!r} key {pointer!r}"
    if not zero_if_absent:
        return None if raw is None else checked_stat(raw, where)
    # x_i lists only the classes a sample has, so the ensemble's K and mean skip the samples
    # without one: recompute with 0 for every sample that has an analysis at all.
    present = present_seeds(src)
    if present is None:
        return None if raw is None else checked_stat(raw, where)
    values = raw.get("values") if isinstance(raw, dict) else None
    if raw is not None and not isinstance(values, list):
        return checked_stat(raw, where)
    values = values or [None] * len(present)
    filled = [0.0 if v is None else float(v) for v, p in zip(values, present) if p]
    return mean_sd(filled)


def scaled(s, factor):
    if s is None or s.mean is None:
        return s
    return s._replace(mean=s.mean * factor, sd=None if s.sd is None else s.sd * factor)


def quantity_stat(src, q):
    """The Stat of quantity q in the source, in the paper's unit, with its count if any."""
    s = scaled(stat(src, q.pointer, q.zero_if_absent), q.scale)
    if s is not None and s.mean is not None and q.grain_fraction:
        s = s._replace(grains=ensemble_n(src.ensemble), scale=q.scale)
    return s


# ---------------------------------------------------------------- cells

def paper_error(ref):
    """Standard error of [AR]'s printed mean: sd/sqrt(5) where they give a sd; where they do
    not, the rounding of the printed digits, uniform over +-half-width (half-width/sqrt(3))."""
    if ref["sd"] is not None:
        return ref["sd"] / math.sqrt(PAPER_SAMPLES)
    return ref.get("rounding", 0.0) / math.sqrt(3.0)


def deviation(ours, ref):
    """(ours − paper) / combined standard error, ±inf when that error is 0 and they differ.

    A fraction of grains is a count: measured on K samples of n grains it cannot be known
    better than the binomial error sqrt(p (1 − p) / (K n)), whatever the samples' scatter says
    (four samples without an 11-coordinated grain have sd 0, yet [AR]'s 0.02 % is 4 grains in
    20 000). Each side's error is therefore at least its binomial error at the pooled p."""
    var_ours, var_paper = ours.sd ** 2 / ours.K, paper_error(ref) ** 2
    if ours.grains:
        pooled = (ours.mean * ours.K + ref["value"] * PAPER_SAMPLES) / (ours.K + PAPER_SAMPLES)
        p = min(max(pooled / ours.scale, 0.0), 1.0)
        unit = ours.scale ** 2 * p * (1.0 - p) / ours.grains
        var_ours = max(var_ours, unit / ours.K)
        var_paper = max(var_paper, unit / PAPER_SAMPLES)
    se = math.sqrt(var_ours + var_paper)
    diff = ours.mean - ref["value"]
    if se > 0:
        return diff / se
    return 0.0 if diff == 0 else math.copysign(math.inf, diff)


def fmt_num(v, dec):
    return f"{v + 0.0:.{dec}f}"


def fmt_ours(s, dec):
    if s is None:
        return "absent"  # granpack ensemble leaves out keys no sample has a number for
    if s.mean is None:
        return "null (K=0)"
    if s.K < 2 or s.sd is None:
        return f"{fmt_num(s.mean, dec)} (K={s.K})"
    return f"{fmt_num(s.mean, dec)} ± {fmt_num(s.sd, dec)}"


def fmt_dev(s, ref):
    if ref is None or s is None or s.mean is None:
        return "—"
    if ref["kind"] == "bound":
        return "below bound" if s.mean < ref["value"] else "ABOVE bound"
    if s.K < 2 or s.sd is None:
        return f"K={s.K}"
    d = deviation(s, ref)
    return f"{d:+.2f}" if math.isfinite(d) else ("+inf" if d > 0 else "-inf")


def column_decimals(texts):
    """Decimals for our values in one column: the paper's finest exact value, plus one."""
    decs = [paper.decimals(t) for t in texts
            if t is not None and paper.parse(t)["kind"] == "value" and paper.parse(t)["value"]]
    return (max(decs) if decs else 1) + 1


def cell_decimals(text, column_dec):
    """The paper value's own precision plus one digit; the column's for 0, ~, < or n. d."""
    ref = paper.parse(text)
    if ref is None or ref["kind"] != "value" or ref["value"] == 0:
        return column_dec
    return paper.decimals(text) + 1


# ---------------------------------------------------------------- table specifications

def x_i_quantities(key, count):
    return [Quantity(f"x_{i}", f"/{key}/{i}", 100.0, True, True) for i in range(count)]


def state_quantities(columns):
    """Phi, z*, x0, x2, Z(2), M1, M2 (and H/N_f*) of tables III and IV, in the paper's units."""
    known = {"Φ": ("/phi", 1.0), "z*": ("/z_star", 1.0), "x0": ("/x0", 100.0),
             "x2": ("/x2", 100.0), "Z(2)": ("/Z_2", 1.0), "M1": ("/M1", 1.0),
             "M2": ("/M2", 1.0), "H/N_f*": ("/H_over_Nf", 1.0)}
    fractions = {"x0", "x2"}
    return [Quantity(c, known[c][0], known[c][1], False, c in fractions) for c in columns]


def treatment_state(row_label):
    """Paper row "A' (II)" -> our state "A'(II)"; "(I)" rows use the plain state."""
    state, treatment = row_label.rsplit(" ", 1)
    return state if treatment == "(I)" else state + treatment


def spec_x_i(table):
    rows = []
    for label, texts in table.items():
        key = "x_i" if label.endswith("(I)") else "x_i_all_contacts"
        rows.append(RowSpec(label, treatment_state(label), x_i_quantities(key, len(texts)),
                            texts, ""))
    return rows


def spec_table_ii():
    names = ("Z", "Z_cr", "Q6_global", "Q6_local_mean", "Q6_local_crystalline",
             "crystalline_fraction", "cluster_mass_average")
    rows = []
    for (state, dc), texts in paper.TABLE_II.items():
        qs = [Quantity(c, f"/order/{dc}/{k}", 1.0, False)
              for c, k in zip(paper.TABLE_II_COLUMNS, names)]
        rows.append(RowSpec(f"{state}, d_c = {dc} a", state, qs, texts, ""))
    return rows


def spec_table_iii():
    qs = state_quantities(paper.STATE_COLUMNS)
    rows = []
    for state, row in paper.TABLE_III.items():
        origin, p_kpa, zeta, i_max = row["conditions"]
        cond = f"{origin}, {p_kpa} kPa, ζ = {zeta}, I_max = {i_max}"
        rows.append(RowSpec(state, state, qs, row["values"], cond))
    return rows


def spec_table_iv():
    qs = state_quantities(paper.TABLE_IV_COLUMNS)
    return [RowSpec(state, state, qs,
                    tuple(cells.get(c, (None,))[0] for c in paper.TABLE_IV_COLUMNS), "")
            for state, cells in paper.TABLE_IV.items()]


def spec_table_vi():
    keys = ["/X1", "/M1", "/M2"]
    for group in ("divalent_contacts", "trivalent_contacts"):
        keys += [f"/{group}/{k}" for k in ("N_over_Pa2", "X1", "M1", "M2")]
    qs = [Quantity(c, k, 1.0, False) for c, k in zip(paper.TABLE_VI_COLUMNS, keys)]
    return [RowSpec(state, state, qs, texts, "") for state, texts in paper.TABLE_VI.items()]


def spec_order(table):
    rows = []
    for state, by_dc in table.items():
        window = paper.ORDER_WINDOW[state]
        for dc, texts in by_dc.items():
            key = f"{float(dc):.2f}"  # granpack analyze writes d_c as "1.10"
            qs = [Quantity(c, f"/order/{key}/windows/{window}/{c}", 100.0, False)
                  for c in paper.ORDER_COLUMNS]
            rows.append(RowSpec(f"{state}, d_c = {dc} a", state, qs, texts,
                                f"window {window}"))
    return rows


TABLES = {
    "I": ("Table I: x_i (%) of grains with i contacts, frictionless A and A' "
          "((II): rattlers fixed)", lambda: spec_x_i(paper.TABLE_I)),
    "II": ("Table II: bond order of A and A' (bonds shorter than d_c)", spec_table_ii),
    "III": ("Table III: D states (gas: compressed from the gas at P; QS: quasistatically "
            "from 1 kPa)", spec_table_iii),
    "IV": ("Table IV: isotropic states (A', Z and H/N_f* from the text, sec. III A, "
           "IV E-F; x0, x2 in %)", spec_table_iv),
    "V": ("Table V: x_i (%) of the frictional states B, C, D ((II): rattlers fixed)",
          lambda: spec_x_i(paper.TABLE_V)),
    "VI": ("Table VI: strong/weak split and friction mobilisation", spec_table_vi),
    "VII": ("Table VII: % of grains in the (Q4, Q6) windows of Aste et al.'s dense "
            "sample F", lambda: spec_order(paper.TABLE_VII)),
    "VIII": ("Table VIII: % of grains in the windows of Aste et al.'s samples D (for B) "
             "and B (for D)", lambda: spec_order(paper.TABLE_VIII)),
}


# ---------------------------------------------------------------- printing

def row_stats(spec, src):
    return [quantity_stat(src, q) for q in spec.quantities]


def md_row(cells):
    return "| " + " | ".join(cells) + " |"


def print_table(key, sources):
    title, build = TABLES[key]
    specs = build()
    columns = [q.label for q in specs[0].quantities]
    col_dec = [column_decimals([s.paper[i] for s in specs]) for i in range(len(columns))]
    print(f"### {title}\n")
    print(md_row(["state", "row"] + columns))
    print(md_row(["---"] * (len(columns) + 2)))
    for spec in specs:
        for line in row_group(spec, sources.get(spec.state), col_dec):
            print(md_row(line))
    print()


def row_group(spec, src, col_dec):
    """The three lines of one paper row: ours, [AR], dev."""
    refs = [paper.parse(t) for t in spec.paper]
    decs = [cell_decimals(t, d) for t, d in zip(spec.paper, col_dec)]
    label = spec.label + (f" ({spec.note})" if spec.note else "")
    paper_line = [label, "[AR]"] + [("n. d." if t is None else t) for t in spec.paper]
    if src is None:
        n = len(refs)
        return [[label, "ours"] + ["not run"] * n, paper_line, [label, "dev"] + ["—"] * n]
    stats = row_stats(spec, src)
    ks = [s.K for s in stats if s is not None and s.mean is not None]
    k_label = f"ours (K={max(ks)})" if ks else "ours"
    ours = [fmt_ours(s, d) for s, d in zip(stats, decs)]
    devs = [fmt_dev(s, r) for s, r in zip(stats, refs)]
    return [[label, k_label] + ours, paper_line, [label, "dev"] + devs]


def print_sources(by_state):
    print("| state | file | configuration | n | finished samples (K) | unfinished | used for |")
    print("|---|---|---|---|---|---|---|")
    for state, srcs in by_state.items():
        chosen = table_source(srcs)
        for s in srcs:
            seeds = s.ensemble.get("seeds") or []
            unfinished = s.ensemble.get("unfinished") or []
            print(md_row([state, s.path, s.stem, str(ensemble_n(s.ensemble)),
                          f"{len(seeds)} (seeds {seed_list(seeds)})",
                          seed_list(unfinished) or "none",
                          "tables, figures" if s is chosen else "fig. 1"]))
    print()


def seed_list(seeds):
    return ", ".join(str(s) for s in seeds)


def print_tables(tables, by_state):
    chosen = {state: table_source(srcs) for state, srcs in by_state.items()}
    print("## [AR] tables from granpack ensembles\n")
    print("Each state: our mean ± sample sd over K samples (`ours`), [AR]'s value ± its "
          "sd over 5 samples, and dev = (ours − [AR]) / sqrt(sd²/K + sd_[AR]²/5). "
          "`n. d.`: no value in [AR]; `not run`: no ensemble given.\n")
    if by_state:
        print_sources(by_state)
    for key in tables:
        print_table(key, chosen)


# ---------------------------------------------------------------- tolerances and --check

def tolerance_cells():
    """(state, quantity) -> (paper text, source) of every table IV cell with a paper value."""
    return {(state, q): cell for state, cells in paper.TABLE_IV.items()
            for q, cell in cells.items() if cell[0] is not None}


def split_md_row(line):
    cells = line.strip().strip("|").split("|")
    return [c.strip().strip("`").strip() for c in cells]


def is_separator(line):
    return all(re.fullmatch(r":?-+:?", c) for c in split_md_row(line))


def find_tolerance_table(path, lines):
    """(line number, text) of the table rows under the tolerance heading."""
    try:
        start = next(i for i, l in enumerate(lines) if l.strip() == TOLERANCE_HEADING)
    except StopIteration:
        raise InputError(f"{path}: no heading \"{TOLERANCE_HEADING}\"")
    # The first run of "|" lines under the heading whose second line is a separator
    # (prose may start a line with "|", a table always has |---|).
    rows = []
    for i in range(start + 1, len(lines)):
        text = lines[i].strip()
        if text.startswith("#"):
            break
        if text.startswith("|"):
            rows.append((i + 1, text))
            continue
        if len(rows) >= 2 and is_separator(rows[1][1]):
            break
        rows = []
    if len(rows) < 2 or not is_separator(rows[1][1]):
        raise InputError(f"{path}: no Markdown table under \"{TOLERANCE_HEADING}\" (line "
                         f"{start + 1}); expected columns | {' | '.join(TOLERANCE_COLUMNS)} |")
    return rows


def parse_tolerance_value(text, path, lineno):
    if text.lower() in ("inf", "∞"):
        return math.inf
    try:
        value = float(text)
    except ValueError:
        value = None
    if value is None or not value > 0 or math.isnan(value):
        raise InputError(f"{path} line {lineno}: tolerance {text!r} is not allowed; "
                         "write a number > 0 (in combined standard errors), or inf to print "
                         "the cell without enforcing it")
    return value


def parse_tolerances(path):
    """{(state, quantity): (tolerance, line number)} from the Markdown tolerance table."""
    try:
        lines = Path(path).read_text().splitlines()
    except FileNotFoundError:
        raise InputError(f"{path}: no such file (the tolerance declaration)")
    except (OSError, UnicodeDecodeError) as e:
        raise InputError(f"{path}: cannot read ({e})")
    rows = find_tolerance_table(path, lines)
    head_no, head = rows[0]
    if tuple(c.lower() for c in split_md_row(head)) != TOLERANCE_COLUMNS:
        raise InputError(f"{path} line {head_no}: the header must be "
                         f"| {' | '.join(TOLERANCE_COLUMNS)} |, found {head}")
    cells = tolerance_cells()
    out = {}
    for lineno, text in rows[2:]:
        key, tol = parse_tolerance_row(path, lineno, text, cells)
        if key in out:
            raise InputError(f"{path} line {lineno}: {key[0]} {key[1]} is declared twice "
                             f"(first on line {out[key][1]})")
        out[key] = (tol, lineno)
    return out


def parse_tolerance_row(path, lineno, text, cells):
    parts = split_md_row(text)
    if len(parts) != 4:
        raise InputError(f"{path} line {lineno}: expected 4 cells "
                         f"(| {' | '.join(TOLERANCE_COLUMNS)} |), found {len(parts)}")
    state, quantity, tol_text, why = parts
    state = normal_state(state)
    quantity = {"Phi": "Φ", "phi": "Φ"}.get(quantity, quantity)
    if state not in paper.TABLE_IV:
        raise InputError(f"{path} line {lineno}: unknown state {state!r}; allowed: "
                         f"{', '.join(paper.TABLE_IV)}")
    if (state, quantity) not in cells:
        allowed = [q for (s, q) in cells if s == state]
        raise InputError(f"{path} line {lineno}: {state} has no [AR] value for quantity "
                         f"{quantity!r}; allowed for {state}: {', '.join(allowed)}")
    if not why:
        raise InputError(f"{path} line {lineno}: the \"why\" cell is empty; say where the "
                         "paper value comes from and why this tolerance")
    return (state, quantity), parse_tolerance_value(tol_text, path, lineno)


def check_cells(chosen, tolerances, tol_path):
    """Rows (state, quantity, stat, ref, dev, tolerance) of every checkable table IV cell."""
    cells = tolerance_cells()
    quantities = {q.label: q for q in state_quantities(paper.TABLE_IV_COLUMNS)}
    out = []
    for (state, label), (text, _source) in cells.items():
        src = chosen.get(state)
        if src is None:
            continue
        if (state, label) not in tolerances:
            raise InputError(f"{tol_path}: no tolerance declared for {state} {label} (add a "
                             f"row under \"{TOLERANCE_HEADING}\")")
        q = quantities[label]
        s = quantity_stat(src, q)
        if s is None or s.mean is None:
            raise InputError(f"{src.path}: analysis {src.stem!r} has no value for key "
                             f"{q.pointer!r} (needed for table IV, {state} {label})")
        ref = paper.parse(text)
        dev = deviation(s, ref) if s.K >= 2 and s.sd is not None else None
        out.append((state, label, s, ref, dev, tolerances[(state, label)][0]))
    return out


def run_check(tol_path, by_state):
    tolerances = parse_tolerances(tol_path)
    chosen = {state: table_source(srcs) for state, srcs in by_state.items()}
    rows = check_cells(chosen, tolerances, tol_path)
    if not rows:
        raise InputError("--check: none of the given states has a table IV value to check "
                         f"(states with [AR] values: {', '.join(paper.TABLE_IV)})")
    bad = [r for r in rows if r[4] is not None and abs(r[4]) > r[5]]
    for state in paper.TABLE_IV:
        if state not in chosen:
            note(f"check: state {state} not given, its table IV cells are not checked")
    for state, label, s, ref, dev, tol in rows:
        if dev is None:
            note(f"check: {state} {label}: K={s.K}, no deviation, not checked")
    for state, label, s, ref, dev, tol in bad:
        dec = cell_decimals(ref["text"], 4)
        print(f"FAIL table IV {state} {label}: ours {fmt_ours(s, dec)} (K={s.K}), "
              f"[AR] {ref['text']}, dev {fmt_dev(s, ref)}, allowed |dev| <= {tol:g}")
    checked = sum(1 for r in rows if r[4] is not None)
    print(f"table IV check: {checked} cells checked against {tol_path}, "
          f"{len(bad)} outside tolerance")
    return 1 if bad else 0


# ---------------------------------------------------------------- figures

def figure_sources(by_state, names):
    return {s: by_state[s] for s in names if s in by_state}


def array_stat(src, pointer):
    """(mean, sd) arrays of a curve of the source's stem, or None."""
    import numpy as np
    raw = src.ensemble["analysis"][src.stem].get(pointer)
    if not isinstance(raw, dict) or not isinstance(raw.get("mean"), list):
        return None
    nan = float("nan")
    mean = np.array([nan if v is None else v for v in raw["mean"]], dtype=float)
    sd_raw = raw.get("sd") if isinstance(raw.get("sd"), list) else [None] * len(mean)
    sd = np.array([nan if v is None else v for v in sd_raw], dtype=float)
    return mean, sd


def paper_point(text):
    ref = paper.parse(text)
    return ref["value"], ref["sd"] or 0.0


def fig1(plt, by_state, out):
    """[AR] fig. 1: Phi against n^(-1/2) for A and A', one point per ensemble file."""
    srcs = figure_sources(by_state, ("A", "A'"))
    if not srcs:
        return None, "fig. 1 needs state A or A'"
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    style = {"A": ("o", "black"), "A'": ("s", "tab:red")}
    for state, group in srcs.items():
        pts = []
        for s in group:
            n, phi = ensemble_n(s.ensemble), stat(s, "/phi")
            if n and phi is not None and phi.mean is not None:
                pts.append((n ** -0.5, phi.mean, phi.sd or 0.0, phi.K))
        marker, color = style[state]
        for i, (x, y, e, k) in enumerate(pts):
            ax.errorbar(x, y, yerr=e, fmt=marker, color=color, ms=7, capsize=4,
                        label=f"{state}, ours (± sd)" if i == 0 else None)
            ax.annotate(f"K={k}", (x, y), textcoords="offset points", xytext=(-8, -3),
                        ha="right", fontsize=8)
        n_text, phi_text = paper.FIG_1[state]
        y, e = paper_point(phi_text)
        ax.errorbar(int(n_text) ** -0.5 + 0.0006, y, yerr=e, fmt=marker, mfc="none",
                    color=color, ms=7, capsize=4, label=f"{state}, [AR] {phi_text}")
    ax.set_xlim(0, 0.035)
    ax.set_xlabel(r"$n^{-1/2}$")
    ax.set_ylabel(r"$\Phi$")
    ax.set_title("[AR] fig. 1: solid fraction against sample size\n"
                 "([AR] points shifted right by 0.0006 for legibility)", fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    return save(fig, out / "fig1.png"), None


def fig2_points(src):
    """Per pressure level (report stages and pressure_steps levels at or above the base
    configuration's pressure): (dPhi mean, sd, 1/kappa mean, sd), from per-sample values."""
    base = src.ensemble["analysis"][src.stem]
    phi0 = per_seed(base.get("/phi0"))
    base_kappa = stat(src, "/kappa")
    if phi0 is None or base_kappa is None:
        return None
    report = src.ensemble["report"]
    seen, pts = set(), []
    for ptr in report:
        m = re.fullmatch(r"(/stages/[^/]+(?:/levels/\d+)?)/phi", ptr)
        if not m:
            continue
        phi, kappa = per_seed(report[ptr]), per_seed(report.get(m.group(1) + "/kappa"))
        if phi is None or kappa is None:
            continue
        both = [(p - p0, 1.0 / k) for p, p0, k in zip(phi, phi0, kappa)
                if None not in (p, p0, k) and k > 0]
        # A "write" stage repeats the state before it; keep each level once, and only the
        # levels at or above the base pressure (compressions, as in [AR] fig. 2).
        key = tuple(round(v, 12) for pair in both for v in pair)
        if not both or key in seen:
            continue
        dphi, inv_k = mean_sd([b[0] for b in both]), mean_sd([b[1] for b in both])
        if inv_k.mean < 0.999999 / base_kappa.mean:
            continue
        seen.add(key)
        pts.append((dphi, inv_k))
    return sorted(pts, key=lambda p: p[1].mean)


def per_seed(raw):
    """The per-sample values of a scalar STAT (None where absent), or None."""
    if not isinstance(raw, dict) or not isinstance(raw.get("values"), list):
        return None
    return [None if v is None else float(v) for v in raw["values"]]


def eq28_slope(src):
    """dPhi per unit 1/kappa from [AR] eq. (28) with the base configuration's means."""
    phi, z53, z = (stat(src, k) for k in ("/phi", "/Z_5_3", "/z"))
    if None in (phi, z53, z):
        return None
    return 3 ** (5 / 3) * phi.mean ** (1 / 3) * z53.mean * (math.pi / z.mean) ** (2 / 3)


def fig2(plt, inputs, out):
    """[AR] fig. 2: 1/kappa against dPhi = Phi − Phi0, Phi0 from eq. (28) at the lowest P."""
    if not inputs:
        return None, "fig. 2 needs --fig2 FILE:STEM (an ensemble of pressure steps)"
    fig, axes = plt.subplots(1, len(inputs), figsize=(5.6 * len(inputs), 4.6), squeeze=False)
    for ax, (label, src) in zip(axes[0], inputs):
        pts = fig2_points(src)
        if not pts:
            plt.close(fig)
            return None, (f"fig. 2: {src.path}:{src.stem} has no /phi0, /kappa or report "
                          "stages with phi and kappa")
        x = [p[0].mean for p in pts]
        ax.errorbar(x, [p[1].mean for p in pts], xerr=[p[0].sd or 0 for p in pts],
                    yerr=[p[1].sd or 0 for p in pts], fmt="o", color="black", capsize=3,
                    label=f"ours, mean ± sd of K={pts[0][0].K}")
        slope = eq28_slope(src)
        if slope:
            xs = [0.0, max(max(x), 0.0) * 1.1]
            ax.plot(xs, [v / slope for v in xs], ":", color="tab:blue",
                    label="eq. (28), through the lowest P")
        ax.set_xlabel(r"$\Delta\Phi = \Phi - \Phi_0$")
        ax.set_ylabel(r"$\kappa^{-1} = (P/\tilde E)^{2/3}$")
        ax.set_title(f"[AR] fig. 2: {label}", fontsize=10)
        ax.ticklabel_format(style="sci", scilimits=(-3, 3))
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    return save(fig, out / "fig2.png"), None


def dts_fit(f):
    c = {k: float(v) for k, v in paper.DTS_FIT.items()}
    return [(c["a"] * x * x + c["b"] - c["c"] / (1 + c["d"] * x)) * math.exp(-c["e"] * x)
            for x in f]


def fig4(plt, by_state, out):
    """[AR] fig. 4: P(f), f = N/<N>, of A and A' with the DTS fit."""
    srcs = {s: table_source(g) for s, g in figure_sources(by_state, ("A", "A'")).items()}
    curves = {}
    for state, src in srcs.items():
        edges, pdf = array_stat(src, "/P_f/f_edges"), array_stat(src, "/P_f/pdf")
        if edges is not None and pdf is not None:
            e = edges[0]
            curves[state] = ((e[:-1] + e[1:]) / 2, pdf[0], pdf[1], src)
    if not curves:
        return None, "fig. 4 needs /P_f/f_edges and /P_f/pdf of state A or A'"
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.4))
    colors = {"A": "tab:red", "A'": "tab:blue"}
    for ax, log in zip(axes, (False, True)):
        for state, (f, m, sd, src) in curves.items():
            ax.errorbar(f, m, yerr=sd, fmt="+" if state == "A" else "x", ms=5, capsize=2,
                        color=colors[state], label=f"{state}, ours (± sd, K={stat_k(src)})")
        fmax = max(c[0].max() for c in curves.values())
        fs = [fmax * i / 400 for i in range(401)]
        ax.plot(fs, dts_fit(fs), "--", color="gray", label="DTS fit ([AR] fig. 4)")
        ax.set_xlabel(r"$f = N/\langle N\rangle$")
        ax.set_ylabel(r"$P(f)$")
        if log:
            ax.set_yscale("log")
            ax.set_ylim(1e-3, None)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle("[AR] fig. 4: distribution of normal forces, A and A'", fontsize=11)
    return save(fig, out / "fig4.png"), None


def stat_k(src):
    s = stat(src, "/phi")
    return s.K if s is not None else "?"


def zh_curve(src):
    """(h, z(h) − z(0), sd of z(h)) for h > 0 from /z_h, or None."""
    h, z = array_stat(src, "/z_h/h_over_a"), array_stat(src, "/z_h/z_I")
    if h is None or z is None or not len(h[0]) or h[0][0] != 0:
        return None
    return h[0][1:], z[0][1:] - z[0][0], z[1][1:]


def fit_line(src, pointer):
    beta, amp = stat(src, pointer + "/beta"), stat(src, pointer + "/A")
    return None if beta is None or amp is None else (amp.mean, beta)


def fig_zh(plt, by_state, state, out):
    """[AR] figs. 10-12: z^I(h) − z and z^II(h) − z^II(0) on log-log axes."""
    info = paper.FIG_ZH[state]
    srcs = {t: table_source(by_state[s]) for t, s in (("I", state), ("II", state + "(II)"))
            if s in by_state}
    if not srcs:
        return None, f"fig. {info['figure']} needs state {state} or {state}(II)"
    fig, ax = plt.subplots(figsize=(6.6, 4.8))
    colors = {"I": "black", "II": "tab:blue"}
    drawn = False
    for t, src in srcs.items():
        drawn |= draw_zh(ax, src, t, colors[t], info)
    if not drawn:
        plt.close(fig)
        return None, f"fig. {info['figure']}: no /z_h curves for {state} or {state}(II)"
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlim(1e-5, 0.6)
    ax.set_ylim(1e-3, None)
    ax.set_xlabel(r"$h/a$")
    ax.set_ylabel(r"$z(h) - z(0)$")
    ax.set_title(f"[AR] fig. {info['figure']}: {state} samples "
                 "(error bars: sd of z(h) over samples)", fontsize=10)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8, loc="lower right")
    return save(fig, out / f"fig{info['figure']}_{state}.png"), None


def draw_zh(ax, src, treatment, color, info):
    import numpy as np
    curve = zh_curve(src)
    if curve is None:
        return False
    h, dz, sd = curve
    keep = (h > 0) & (dz > 0)
    ax.errorbar(h[keep], dz[keep], yerr=sd[keep], fmt="o", ms=3, color=color, capsize=2,
                elinewidth=0.8, label=f"$z^{{{treatment}}}(h) - z^{{{treatment}}}(0)$, ours")
    fit = fit_line(src, "/z_h_fit_I")
    if fit is None:
        return True
    # Our eq. (35) fit over its window, and [AR]'s slope drawn through the same point at
    # h = 0.01 a but shifted down by 2, so that the two slopes can be compared by eye.
    amp, beta = fit
    hs = np.geomspace(FIT_H_MIN, FIT_H_MAX, 20)
    sd_text = f" ± {beta.sd:.3f}" if beta.sd is not None else ""
    ax.plot(hs, amp * hs ** beta.mean, "-", color=color, lw=2.5, alpha=0.45, zorder=1,
            label=f"our fit of eq. (35): β = {beta.mean:.3f}{sd_text}")
    ref_beta = float(info["beta_" + treatment])
    anchor = amp * 0.01 ** beta.mean / 2
    ax.plot(hs, anchor * (hs / 0.01) ** ref_beta, "--", color=color, lw=1,
            label=f"slope of [AR]'s β_{treatment} = {info['beta_' + treatment]} (shifted down)")
    return True


def save(fig, path):
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    import matplotlib.pyplot as plt
    plt.close(fig)
    return path


def write_figures(directory, by_state, fig2_inputs):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    out = Path(directory)
    out.mkdir(parents=True, exist_ok=True)
    jobs = [lambda: fig1(plt, by_state, out), lambda: fig2(plt, fig2_inputs, out),
            lambda: fig4(plt, by_state, out)]
    jobs += [lambda s=s: fig_zh(plt, by_state, s, out) for s in paper.FIG_ZH]
    for job in jobs:
        path, why = job()
        if path:
            note(f"wrote {path}")
        elif why:
            note(f"skipped: {why}")


# ---------------------------------------------------------------- command line

def parse_args(argv):
    ap = argparse.ArgumentParser(prog=PROG, description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--state", action="append", default=[], metavar="STATE=FILE:STEM",
                    help="a state and the ensemble file and configuration stem it comes from "
                         "(repeatable)")
    ap.add_argument("--tables", default=",".join(ALL_TABLES),
                    help="comma-separated tables to print (default: all): " + ",".join(ALL_TABLES))
    ap.add_argument("--figures", metavar="DIR", help="write the figures (PNG) into DIR")
    ap.add_argument("--fig2", action="append", default=[], metavar="[LABEL=]FILE:STEM",
                    help="fig. 2: an ensemble of pressure steps and the stem of its "
                         "lowest-pressure configuration (repeatable, one panel each)")
    ap.add_argument("--check", metavar="TOLERANCES.md",
                    help="check table IV against the tolerances declared in this Markdown file "
                         "(exit 1 if any is exceeded) instead of printing the tables")
    return ap.parse_args(argv)


def parse_tables(text):
    tables = [t.strip().upper() for t in text.split(",") if t.strip()]
    bad = [t for t in tables if t not in ALL_TABLES]
    if bad or not tables:
        raise InputError(f"--tables {text!r}: unknown table {', '.join(bad) or '(none)'}; "
                         f"allowed: {','.join(ALL_TABLES)}")
    return tables


def parse_fig2(text, cache):
    label, sep, rest = text.rpartition("=")  # the label may contain "=", the path may not
    if not sep or ":" not in rest:
        label, rest = "", text
    src = parse_source("fig2=" + rest, cache)
    return (label or f"{src.path}:{src.stem}", src)


def main(argv=None):
    args = parse_args(argv)
    try:
        tables = parse_tables(args.tables)
        cache, by_state = {}, {}
        for text in args.state:
            src = parse_source(text, cache)
            by_state.setdefault(src.state, []).append(src)
        fig2_inputs = [parse_fig2(t, cache) for t in args.fig2]
        if args.check:
            return run_check(args.check, by_state)
        print_tables(tables, by_state)
        if args.figures:
            write_figures(args.figures, by_state, fig2_inputs)
    except InputError as e:
        print(f"{PROG}: error: {e}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
