#!/usr/bin/python3
"""The deck that reads a granpack file back: its stored deck up to the first [[stage]], then one
`read` stage of the file itself (render_pictures.sh runs it to redraw a committed packing).

  /usr/bin/python3 jobs/tools/read_deck.py FILE.h5 OUT.toml
"""
import argparse
import os

import granpack_io as gio


def main(argv=None):
    ap = argparse.ArgumentParser(prog="read_deck.py", description=__doc__.split("\n\n")[0])
    ap.add_argument("packing", metavar="FILE.h5", help="a granpack configuration")
    ap.add_argument("out", metavar="OUT.toml", help="the deck written")
    a = ap.parse_args(argv)
    try:
        p = gio.read_packing(a.packing)
    except gio.GranpackFileError as e:
        gio.fail("read_deck.py", e)
    head = p.deck.split("[[stage]]")[0]
    with open(a.out, "w") as f:
        f.write(head + f'\n[[stage]]\nkind = "read"\nfile = "{os.path.abspath(a.packing)}"\n')


if __name__ == "__main__":
    main()
