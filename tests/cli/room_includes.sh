#!/usr/bin/env bash
# The rooms of include/granpack and src include only from their own room and the rooms below
# it (docs/ARCHITECTURE.md, "Rooms and what they may include"): a header from a room above,
# e.g. engine/ including stages/ or app/, fails here, and so does a room this table does not
# know (a new room says here what it may include). The physics rooms also include no MPI,
# HDF5 or PETSc header (the build refuses <mpi.h> there already; this names the file).
# Outside comm/ no MPI function is called (issue 30): reductions, broadcasts, gathers, scans,
# barriers and a communicator's rank and size go through the helpers of comm/, so each
# collective is written once; only io/ sets up MPI-IO hints (MPI_Info_*).
# A text scan of the #include lines and the code, no build needed.
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

check_python "outside comm/ every MPI call goes through a helper of comm/" "$scratch/mpi_calls.txt" \
  "$GRANPACK_SOURCE_DIR" <<'PY'
import pathlib, re, sys

root = pathlib.Path(sys.argv[1])
call = re.compile(r"\bMPI_[A-Z][A-Za-z_]*\s*\(")
allowed = {"io": re.compile(r"\bMPI_Info_[a-z_]+\s*\(")}  # MPI-IO hints, not communication
bad = []
files = sorted(root.glob("include/granpack/*/*")) + sorted(root.glob("src/*/*"))
for f in files:
    room = f.parent.name
    if room == "comm":
        continue
    for n, line in enumerate(f.read_text(errors="replace").splitlines(), 1):
        code = line.split("//")[0]
        for m in call.finditer(code):
            if room in allowed and allowed[room].match(code, m.start()):
                continue
            bad.append(f"{f.relative_to(root)}:{n}: {room}/ calls {m.group(0).rstrip('( ')}: use a helper of comm/")
print(f"{len(files)} files scanned")
for b in bad:
    print(b)
sys.exit(1 if bad else 0)
PY

checks_done room_includes
