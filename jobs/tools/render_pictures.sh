#!/usr/bin/env bash
# The pictures of docs/visualisation.md, from committed files of docs/data: granpack rewrites
# each file (a deck whose one stage reads it, with the file's own [sample] and [material]), which
# gives it its /network group and XDMF sidecar, then jobs/tools/pv_packing.py renders the force
# network under pvbatch (on a virtual X server, jobs/tools/with_xvfb.sh: Debian's ParaView draws
# through X); for a picture of a mode, `granpack stiffness --modes` writes the modes of the
# rewritten file and jobs/tools/pv_modes.py draws one (or, `divalent`, one divalent grain's free
# rolling, zoomed onto the grain with --grain, the contacts from the rewritten file).
#   bash jobs/tools/render_pictures.sh [OUT_DIR [LABEL ...]]
# (OUT_DIR default docs/figures/visualisation; LABELs: only these pictures, e.g. D_divalent_rolling)
# Needs the build (build/granpack, or GRANPACK_EXE) and paraview, python3-paraview, xvfb.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
exe=${GRANPACK_EXE:-$root/build/granpack}
dest=${1:-$root/docs/figures/visualisation}
only=("${@:2}")
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
for tool in pvbatch Xvfb; do
  command -v "$tool" > /dev/null || { echo "render_pictures.sh: $tool not found (apt-get install paraview python3-paraview xvfb)" >&2; exit 2; }
done
[ -x "$exe" ] || { echo "render_pictures.sh: no granpack executable at $exe (build it, or set GRANPACK_EXE)" >&2; exit 2; }
mkdir -p "$dest"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# label  file (under docs/data)  size (W, or WxH)  what (packing: pv_packing.py; mode_K:
# pv_modes.py --mode K; divalent: pv_modes.py --mode divalent) and its options
pictures=(
  "A_strong_network A_n4000_seed1.h5 560 packing --strong 1 --slab 0.35"
  "D_strong_network D_n4000_seed1.h5 560 packing --strong 1 --slab 0.35"
  "GRC_seriesA_P0.01 2d/seriesA_P0.01.h5 600 packing"
  "GRC_three_clusters 2d/v0A_0.095_three_clusters.h5 600 packing --colour cluster_id"
  "A_softest_mode A_n4000_seed1.h5 560 mode_0 --above 0.2"
  "GRC_seriesA_P0.01_softest_mode 2d/seriesA_P0.01.h5 600 mode_0"
  "D_divalent_rolling D_n4000_seed1.h5 640x480 divalent --grain 2565"
)
labels=" $(for entry in "${pictures[@]}"; do printf '%s ' "${entry%% *}"; done)"
for label in "${only[@]}"; do
  [[ "$labels" == *" $label "* ]] || { echo "render_pictures.sh: no picture $label (the pictures:$labels)" >&2; exit 2; }
done
for entry in "${pictures[@]}"; do
  read -r label file size what options <<< "$entry"
  if [ ${#only[@]} -gt 0 ] && [[ " ${only[*]} " != *" $label "* ]]; then continue; fi
  width=${size%x*} height=${size#*x}
  src="$root/docs/data/$file"
  # The stored deck up to its first stage, then one `read` stage of the file itself.
  /usr/bin/python3 "$root/jobs/tools/read_deck.py" "$src" "$work/$label.toml"
  mpiexec -n 2 "$exe" run "$work/$label.toml" -o "$work/$label" -q < /dev/null > "$work/$label.log" 2>&1 \
    || { tail -5 "$work/$label.log" >&2; exit 1; }
  if [ "$what" = packing ]; then
    bash "$root/jobs/tools/with_xvfb.sh" pvbatch "$root/jobs/tools/pv_packing.py" \
      "$work/$label/final.xdmf" --png "$dest/$label.png" --size "$width" "$height" ${options:-} > /dev/null
  else
    mode=${what#mode_} count=1 extra=()
    if [ "$what" = divalent ]; then
      extra=(--packing "$work/$label/final.h5") # the contacts of the zoom
    else
      count=$((mode + 1))
    fi
    OPENBLAS_NUM_THREADS=1 mpiexec -n 2 "$exe" stiffness "$work/$label/final.h5" --modes $count \
      --modes-file "$work/$label/modes.h5" < /dev/null > "$work/$label.stiffness.log" 2>&1 \
      || { tail -5 "$work/$label.stiffness.log" >&2; exit 1; }
    bash "$root/jobs/tools/with_xvfb.sh" pvbatch "$root/jobs/tools/pv_modes.py" \
      "$work/$label/modes.xdmf" --mode "$mode" --png "$dest/$label.png" --size "$width" "$height" \
      "${extra[@]}" ${options:-} > /dev/null
  fi
  # 256 colours (Pillow, which matplotlib brings): a third of the size, the same look.
  /usr/bin/python3 "$root/jobs/tools/quantize_png.py" "$dest/$label.png"
  echo "$dest/$label.png ($(stat -c %s "$dest/$label.png") bytes)"
done
