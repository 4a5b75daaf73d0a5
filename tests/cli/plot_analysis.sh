#!/usr/bin/env bash
# jobs/tools/plot_analysis.py (docs/plots.md): on synthetic `granpack analyze --json` files it
# writes pf.png, gr.png, zh.png and coordination.png (non-empty PNGs) for one file and for two
# overlaid files with --labels; a file lacking keys is skipped, not fatal; a missing or non-JSON
# input, or a wrong --labels count, gives a non-zero exit and a message naming the file.
# ctest: PROCESSORS 1   (one process at a time: ctest -j2 runs another test beside it)
set -u
: "${GRANPACK_SOURCE_DIR:?}"
tool="$GRANPACK_SOURCE_DIR/jobs/tools/plot_analysis.py"
py=/usr/bin/python3
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
cli_scratch
export MPLCONFIGDIR="$scratch/mpl"

# Synthetic analyze output: DTS-shaped P(f), a g(r) with a contact peak, z(h) = z0 + A h^beta.
"$py" - "$scratch" <<'PY'
import json, math, sys
d = sys.argv[1]
def state(z0, A, beta, shift):
    edges = [0.1 * i for i in range(51)]
    pdf = [(3.43 * f * f + 1.45 - 1.18 / (1 + 4.71 * f)) * math.exp(-2.25 * f)
           for f in (e + 0.05 for e in edges[:-1])]
    pdf[-1] = 0.0                                    # an empty bin (log panel)
    r = [0.005 + 0.01 * i for i in range(300)]
    g = [0.0 if x < 0.99 else 30.0 if x < 1.0 else 1.0 + 0.5 * math.exp(-(x - 1.0)) * math.cos(6 * x)
         for x in r]
    h = [0.0] + [1e-6 * (0.5 / 1e-6) ** (k / 59) for k in range(60)]
    zI = [z0 + A * x ** beta for x in h]
    zIII = [z0 + shift + 0.9 * A * x ** beta for x in h]
    x_i = {"0": 0.1, "2": 0.03, "3": 0.14, "4": 0.29, "5": 0.25, "6": 0.13, "7": 0.05, "8": 0.01}
    return {"file": "synthetic.h5", "dimension": 3, "n": 100, "phi": 0.59, "z": 4.07,
            "z_star": 4.55, "P_f": {"f_edges": edges, "pdf": pdf, "fraction_above": 0.0},
            "g_r": {"r_over_a": r, "g_I": g, "g_III": [1.1 * v for v in g]},
            "z_h": {"h_over_a": h, "z_I": zI, "z_III": zIII},
            "z_h_fit_I": {"z0": z0, "A": A, "beta": beta},
            "z_h_fit_III": {"z0": z0 + shift, "A": 0.9 * A, "beta": beta},
            "x_i": x_i, "x_i_all_contacts": x_i,
            "x_i_without_rattlers": {k: v / 0.9 for k, v in x_i.items() if k != "0"}}
json.dump(state(4.1, 7.7, 0.40, 0.4), open(f"{d}/D.json", "w"))
json.dump(state(5.5, 11.6, 0.47, 0.1), open(f"{d}/A.json", "w"))
json.dump({"file": "old.h5", "dimension": 2, "phi": 0.8, "g_r": None, "z_h_fit_I": None},
          open(f"{d}/old2d.json", "w"))
PY
check "synthetic JSON written" "[ -s '$scratch/D.json' ] && [ -s '$scratch/A.json' ]"

check_exit "one file" 0 "$scratch/one.txt" "$py" "$tool" "$scratch/one" "$scratch/D.json"
for f in pf gr zh coordination; do
  check "one file: $f.png is a non-empty PNG" "is_png '$scratch/one/$f.png'"
  check "one file: $f.png listed" "grep -q '$f.png' '$scratch/one.txt'"
done

check_exit "two files + an old 2D file" 0 "$scratch/two.txt" \
  "$py" "$tool" "$scratch/two" "$scratch/D.json" "$scratch/A.json" "$scratch/old2d.json" --labels D,A,old
for f in pf gr zh coordination; do
  check "two files: $f.png is a non-empty PNG" "is_png '$scratch/two/$f.png'"
done
check "the old file's missing data is reported" "grep -q 'old: no g_r' '$scratch/two.txt'"
check "no traceback" "! grep -q Traceback '$scratch/one.txt' '$scratch/two.txt'"

"$py" "$tool" "$scratch/none" "$scratch/old2d.json" > "$scratch/none.txt" 2>&1
check "file with no plottable data: exit 0, nothing written" \
  "[ $? -eq 0 ] && [ ! -e '$scratch/none/pf.png' ] && ! grep -q Traceback '$scratch/none.txt'"

check_refused "missing input, naming the file" '!0' "does_not_exist.json" "$scratch/miss.txt" \
  "$py" "$tool" "$scratch/miss" "$scratch/D.json" "$scratch/does_not_exist.json"
check "missing input: nothing written" "[ ! -e '$scratch/miss/pf.png' ]"

printf '{"P_f": [1, 2' > "$scratch/broken.json"
check_refused "non-JSON input, naming the file" '!0' "broken.json" "$scratch/bad.txt" \
  "$py" "$tool" "$scratch/bad" "$scratch/broken.json"

check_refused "--labels count mismatch" '!0' "labels" "$scratch/lab.txt" \
  "$py" "$tool" "$scratch/lab" "$scratch/D.json" --labels a,b

# [GRC] fig. 23: the eq. (28) model of the tool against closed forms (P_1(x) = x,
# P_2(x) = (3x^2 - 1)/2; d_F = 1 gives Cst + 2 pi A / sqrt(p^2 + k^2)), then ik.png from a 2D file
# with a density block; a 3D file has none and is left out.
"$py" - "$GRANPACK_SOURCE_DIR/jobs/tools" "$scratch" <<'PY' > "$scratch/model.txt" 2>&1
import json, math, sys
sys.path.insert(0, sys.argv[1])
import plot_analysis as t
assert abs(t.legendre_p(1.0, 0.3) - 0.3) < 1e-15, t.legendre_p(1.0, 0.3)
assert abs(t.legendre_p(2.0, 0.5) + 0.125) < 1e-15, t.legendre_p(2.0, 0.5)
ka = [0.1, 1.0, 7.0]
got = t.eq28_over_a2(ka, 1.0, 4.0, 1e-3, 0.05)
for k, g in zip(ka, got):
    want = 1e-3 + 2 * math.pi * 0.05 / math.hypot(0.25, k)
    assert abs(g - want) < 1e-12 * want, (k, g, want)
# a synthetic 2D analysis: I(k) of eq. (28) with d_F = 1.6, xi = 5 a, noise-free
d_f, xi, l, phi, c = 1.6, 5.0, 0.05, 0.3, 1e-4
ks = [0.12 * 1.15 ** i for i in range(40)]
I = list(t.eq28_over_a2(ks, d_f, xi, c, phi * l ** (2 - d_f)))
json.dump({"file": "g.h5", "dimension": 2, "phi": phi,
           "density": {"I_k": {"k_times_a": ks, "I_over_a2": I, "I_error_over_a2": [0.1 * v for v in I]},
                       "fit_eq28": {"d_F": d_f, "d_F_error": 0.05, "xi_over_a": xi, "xi_error_over_a": 0.5,
                                    "constant_over_a2": c, "l_over_a": l, "fractal_regime": True,
                                    "k_range_times_a": [0.12, 6.283]}}},
          open(f"{sys.argv[2]}/G2d.json", "w"))
print("model ok")
PY
check "eq. (28) model against closed forms ($(tail -2 "$scratch/model.txt"))" "grep -q 'model ok' '$scratch/model.txt'"
check_exit "2D density file" 0 "$scratch/ik.txt" "$py" "$tool" "$scratch/ik" "$scratch/G2d.json" "$scratch/D.json"
check "2D density file: ik.png is a non-empty PNG" "is_png '$scratch/ik/ik.png'"
check "3D file left out of ik.png with a note" "grep -q 'D: no density' '$scratch/ik.txt'"
check "3D file alone: no ik.png" "[ ! -e '$scratch/one/ik.png' ]"

checks_done plot_analysis
