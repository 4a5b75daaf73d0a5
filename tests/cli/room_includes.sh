#!/usr/bin/env bash
# The rooms of include/granpack and src include only from their own room and the rooms below
# it (docs/ARCHITECTURE.md, "Rooms and what they may include"): a header from a room above,
# e.g. engine/ including stages/ or app/, fails here, and so does a room this table does not
# know (a new room says here what it may include). The physics rooms also include no MPI,
# HDF5 or PETSc header (the build refuses <mpi.h> there already; this names the file).
# A text scan of the #include lines, no build needed.
# ctest: PROCESSORS 1
set -u
: "${GRANPACK_SOURCE_DIR:?}"
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
cli_scratch

check_python "every #include points to the same room or a room below" "$scratch/rooms.txt" \
  "$GRANPACK_SOURCE_DIR" <<'PY'
import pathlib, re, sys

root = pathlib.Path(sys.argv[1])
physics = ["core", "contact", "neighbor", "dynamics", "analysis"]
# Each room and the rooms it may include from (besides itself). Keep in step with
# docs/ARCHITECTURE.md.
below = {
    "core": [],
    "contact": ["core"],
    "neighbor": ["core", "contact"],
    "dynamics": ["core", "contact", "neighbor"],
    "analysis": ["core", "contact", "neighbor", "dynamics"],
    "comm": physics,
    "io": physics + ["comm"],
    "packing": physics + ["comm", "io"],
    "engine": physics + ["comm", "io"],
    "stages": physics + ["comm", "io", "packing", "engine"],
    "rigidity": physics + ["comm", "io", "packing"],
    "app": physics + ["comm", "io", "packing", "engine", "stages", "rigidity"],
}
granpack_include = re.compile(r'^\s*#\s*include\s*"granpack/([a-z_]+)/')
parallel_header = re.compile(r'^\s*#\s*include\s*[<"](mpi\.h|hdf5\.h|petsc|slepc)')
bad = []
files = sorted(root.glob("include/granpack/*/*")) + sorted(root.glob("src/*/*"))
for f in files:
    room = f.parent.name
    rel = f.relative_to(root)
    if room not in below:
        bad.append(f"{rel}: room '{room}' is not in the table of tests/cli/room_includes.sh")
        continue
    for n, line in enumerate(f.read_text(errors="replace").splitlines(), 1):
        m = granpack_include.match(line)
        if m and m.group(1) != room and m.group(1) not in below[room]:
            bad.append(f"{rel}:{n}: {room}/ includes from {m.group(1)}/, a room above it: {line.strip()}")
        if room in physics and parallel_header.match(line):
            bad.append(f"{rel}:{n}: the physics room {room}/ includes a parallel library: {line.strip()}")
print(f"{len(files)} files scanned")
for b in bad:
    print(b)
sys.exit(1 if bad else 0)
PY

checks_done room_includes
