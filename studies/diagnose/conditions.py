"""Copies of a diagnosis set (a folder with truth.json, models/ and data/, as generate.py writes
or the blind set) read under other acquisition conditions, with the same truth: the answers
should not change.  Writes OUT/<variant>/ for each variant; score each with score.py.

usage: python3 studies/diagnose/conditions.py SET_DIR OUT_DIR

* `v128`    the records as they are, read at their own 128 Hz (no `--decimate`);
* `trunc15` the first 15 s of each record, decimated by 10 (12.8 Hz);
* `sub2`    every second sample (a 64 Hz acquisition, the same noise per sample), decimated by
            5 (12.8 Hz, each kept sample the mean of 5 readings instead of 10: sqrt(2) more noise);
* `dec5`    the records as they are, decimated by 5 (25.6 Hz).

Only the standard library.  OUT_DIR must not be inside the repository (the copies of a set
that is not the project's must not be committed), must not overlap SET_DIR, and must not
already hold a variant: nothing is overwritten, and each variant is written whole or not at all.
"""
import csv
import json
import os
import shutil
import sys

VARIANTS = {
    "v128": ([], lambda rows: rows),
    "trunc15": (["--decimate", "10"], lambda rows: [r for r in rows if float(r[0]) < 15.0]),
    "sub2": (["--decimate", "5"], lambda rows: rows[::2]),
    "dec5": (["--decimate", "5"], lambda rows: rows),
}


def variant(set_dir, out, args, rows_of):
    """Writes one variant of `set_dir` to `out`: the models as they are, each record's rows
    passed through `rows_of`, every case's CLI options replaced by `args`.  Written to a
    sibling folder first (which main() checked is absent) and renamed when whole, so `out` is
    complete or absent."""
    partial = out + ".partial"
    os.makedirs(os.path.join(partial, "data"))
    shutil.copytree(os.path.join(set_dir, "models"), os.path.join(partial, "models"))
    with open(os.path.join(set_dir, "truth.json")) as f:
        truth = json.load(f)
    for case in truth["cases"]:
        # A record is written inside the variant only: a `data` path that is absolute or climbs
        # out with `..` would otherwise land anywhere, the set read included.
        target = os.path.realpath(os.path.join(partial, case["data"]))
        if not inside(target, os.path.realpath(os.path.join(partial, "data"))):
            sys.exit(f"{set_dir}/truth.json: case {case.get('name')!r} has data {case['data']!r} outside "
                     f"its data/ folder; nothing of {out} is kept but {partial}")
        with open(os.path.join(set_dir, case["data"]), newline="") as f:
            rows = list(csv.reader(f))
        with open(target, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(rows[0])
            w.writerows(rows_of(rows[1:]))
        case["args"] = args
    truth["conditions"] = {"from": os.path.abspath(set_dir), "args": args}
    with open(os.path.join(partial, "truth.json"), "w") as f:
        json.dump(truth, f, indent=1)
    os.rename(partial, out)


def inside(path, folder):
    """Whether `path` is `folder` or lies inside it (both resolved)."""
    return path == folder or path.startswith(folder + os.sep)


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    set_dir, out_dir = os.path.realpath(sys.argv[1]), os.path.realpath(sys.argv[2])
    root = os.path.realpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
    if inside(out_dir, root):
        sys.exit("refusing to write the copies inside the repository; use e.g. /tmp/conditions")
    if not os.path.isfile(os.path.join(set_dir, "truth.json")):
        sys.exit(f"{set_dir}/truth.json: not found; SET_DIR is a folder with truth.json, models/, data/")
    outs = {name: os.path.join(out_dir, name) for name in VARIANTS}
    for name, out in outs.items():
        # The variant and the folder it is first written to: neither may overlap the set read
        # nor exist already (nothing is deleted or overwritten).
        for path in (out, out + ".partial"):
            if inside(path, set_dir) or inside(set_dir, path):
                sys.exit(f"refusing to write {path}: it overlaps the set read, {set_dir}; choose another OUT_DIR")
            if os.path.lexists(path):
                sys.exit(f"{path} exists; remove it or choose another OUT_DIR (nothing is overwritten)")
    for name, (args, rows_of) in VARIANTS.items():
        variant(set_dir, outs[name], args, rows_of)
        print(f"wrote {os.path.join(out_dir, name)} ({' '.join(args) or 'no --decimate'})")


if __name__ == "__main__":
    main()
