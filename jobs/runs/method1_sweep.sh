#!/usr/bin/env bash
# [GRC] tables II and III (method 1, without and with cohesion): the deck of the table,
#   II:  jobs/decks/2d/method1_noncohesive_mu0.5.toml (P/K_N = 1e-5, K_N = 1e7 N/m)
#   III: jobs/decks/2d/method1_cohesive_mu0.5.toml    (P* = 0.01, kappa = 1e5, K_N = 1e8 N/m)
# varied over the initial solid fraction Phi_I (0.13, 0.36, 0.52), the friction mu (0.15, 0.5)
# and rolling resistance (off, or table I's K_r = 1e-4 K_N a^2 and mu_r = 1e-2 mu a, with a
# rolling damping zeta_r = 0.01 that [GRC] do not have: without any the packings never meet the
# force criterion, and 0.01 gives the undamped structure; docs/reproduction-2d.md, table III,
# and 4.5; until 2026-12-07 the default was 0.1, which lowers z by 2-5 %). One sample
# (seed 1) each, one after the other, each into out/2d/table<T>/<case>/ (restartable: a
# directory with a checkpoint and no final.h5 is continued through
# jobs/slurm/mpirun_loop.sh), then one line per case from report.json (jobs/tools/case_table.py).
#   bash jobs/runs/method1_sweep.sh TABLE [RANKS] [CASES...]
# TABLE = 2 or 3; CASE = PHI_I-MU-norr|rr, e.g. 0.13-0.5-rr; default: all twelve.
# PRESSURE=P (Pa) replaces the deck's pressure and writes into out/2d/table<T>_p<P>/ instead
# (table III at P* = 0.005: PRESSURE=5.0; docs/reproduction-2d.md, "The collapse under P* = 0.01").
# SEED=S replaces the deck's `seed = 1` and writes into out/2d/table<T>_seed<S>/ (seed 1 stays
# out/2d/table<T>/); jobs/tools/case_table.py BASE... --ensemble pools the seeds per case.
# CELL_MASS=M replaces the deck's `cell_mass = 0.3` (in units of the grains' total mass) and
# writes into out/2d/table<T>_cm<M>[_seed<S>]/ (docs/reproduction-2d.md 4.1, the cell mass).
# ROLLING_DAMPING=Z sets the RR cases' rolling damping zeta_r (default 0.01; 0 is [GRC]'s model)
# and writes into out/2d/table<T>_zr<Z>[_seed<S>]/ (the cases without RR are the same runs).
# A case directory that holds a run (checkpoint or final file) of another deck is refused rather
# than continued or skipped: e.g. an out/2d/table3/ of the old default zeta_r = 0.1.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
table=${1:?usage: method1_sweep.sh TABLE [RANKS] [CASES...]}; shift
case "$table" in
  2) base=method1_noncohesive_mu0.5.toml; k_r=1.0e-3 ;;  # 1e-4 x 1e7 N/m x (1e-3 m)^2
  3) base=method1_cohesive_mu0.5.toml; k_r=1.0e-2 ;;     # 1e-4 x 1e8 N/m x (1e-3 m)^2
  *) echo "method1_sweep: TABLE must be 2 or 3, got '$table'" >&2; exit 2 ;;
esac
ranks=${1:-1}; shift || true
seed=${SEED:-1}
[[ "$seed" =~ ^[0-9]+$ ]] || { echo "method1_sweep: SEED='$seed' is not a non-negative integer" >&2; exit 2; }
cell_mass=${CELL_MASS:-}
[ -z "$cell_mass" ] || [[ "$cell_mass" =~ ^[0-9]*\.?[0-9]+([eE][-+]?[0-9]+)?$ ]] ||
  { echo "method1_sweep: CELL_MASS='$cell_mass' is not a positive number" >&2; exit 2; }
rolling_damping=${ROLLING_DAMPING:-}
[ -z "$rolling_damping" ] || [[ "$rolling_damping" =~ ^[0-9]*\.?[0-9]+$ ]] ||
  { echo "method1_sweep: ROLLING_DAMPING='$rolling_damping' is not a number >= 0" >&2; exit 2; }
suffix=${PRESSURE:+_p$PRESSURE}${cell_mass:+_cm$cell_mass}${rolling_damping:+_zr$rolling_damping}
[ "$seed" = 1 ] || suffix="${suffix}_seed$seed"
cases=${*:-}
if [ -z "$cases" ]; then
  for phi in 0.13 0.36 0.52; do for mu in 0.15 0.5; do for rr in norr rr; do
    cases="$cases $phi-$mu-$rr"; done; done; done
fi
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
# Two 1-rank jobs side by side must not both be bound to core 0 (mpirun's default binding).
export OMPI_MCA_hwloc_base_binding_policy=${OMPI_MCA_hwloc_base_binding_policy:-none}
for c in $cases; do
  IFS=- read -r phi mu rr <<<"$c"
  case "$rr" in norr|rr) ;; *) echo "method1_sweep: case '$c': the third part must be norr or rr" >&2; exit 2;; esac
  dir=$root/out/2d/table$table$suffix/$c
  mkdir -p "$dir"
  /usr/bin/python3 - "$root/jobs/decks/2d/$base" "$dir/deck.toml.new" "$phi" "$mu" "$rr" "$k_r" "${PRESSURE:-}" "$seed" "$cell_mass" "${rolling_damping:-0.01}" <<'PY'
import re, sys
src, dst, phi, mu, rr, k_r, pressure, seed, cell_mass, zeta_r = sys.argv[1], sys.argv[2], float(sys.argv[3]), float(sys.argv[4]), sys.argv[5], sys.argv[6], sys.argv[7], sys.argv[8], sys.argv[9], float(sys.argv[10])
text = open(src).read()
text, n0 = re.subn(r"(?m)^seed = 1$", f"seed = {seed}", text)
assert n0 == 1, f"{src}: one line 'seed = 1' expected, found {n0}"
text, n1 = re.subn(r"(?m)^phi = .*$", f"phi = {phi}", text)
text, n2 = re.subn(r"(?m)^friction = .*$", f"friction = {mu}", text)
assert n1 == 1 and n2 == 1, f"{src} changed shape"
if pressure:
    text, n3 = re.subn(r"(?m)^pressure = .*$", f"pressure = {float(pressure)!r}", text)
    assert n3 == 1, f"{src}: one pressure line expected, found {n3}"
if cell_mass:
    text, n4 = re.subn(r"(?m)^cell_mass = 0\.3$", f"cell_mass = {float(cell_mass)!r}", text)
    assert n4 == 1, f"{src}: one line 'cell_mass = 0.3' expected, found {n4}"
if rr == "rr":
    # table I: K_r = 1e-4 K_N a^2, mu_r = 1e-2 mu a (a = 1e-3 m)
    text = re.sub(r"(?m)^(damping = .*)$",
                  f"\\1\nrolling_stiffness = {k_r}\nrolling_friction = {1e-2 * mu * 1e-3!r}\n"
                  f"rolling_damping = {zeta_r!r}", text)
open(dst, "w").write(f"# generated by jobs/runs/method1_sweep.sh from {src.split('/')[-1]}: "
                     f"Phi_I {phi}, mu {mu}, {rr}, seed {seed}"
                     + (f", cell_mass {cell_mass}" if cell_mass else "") + "\n" + text)
PY
  if [ -e "$dir/deck.toml" ] && { [ -e "$dir/final.h5" ] || [ -e "$dir/checkpoint.h5" ]; } &&
    ! cmp -s "$dir/deck.toml" "$dir/deck.toml.new"; then
    echo "method1_sweep: $dir holds a run of another deck (< its deck.toml, > this call's):" >&2
    diff "$dir/deck.toml" "$dir/deck.toml.new" | grep '^[<>]' | head -8 >&2 || true
    echo "move it away, or choose another output with SEED, CELL_MASS, ROLLING_DAMPING or PRESSURE" >&2
    rm -f "$dir/deck.toml.new"
    exit 2
  fi
  mv "$dir/deck.toml.new" "$dir/deck.toml"
  [ -e "$dir/final.h5" ] || bash "$root/jobs/slurm/mpirun_loop.sh" "$dir/deck.toml" "$dir" "$ranks"
  echo "[method1_sweep] table $table: $c done"
done
/usr/bin/python3 "$root/jobs/tools/case_table.py" "$root/out/2d/table$table$suffix" $cases
