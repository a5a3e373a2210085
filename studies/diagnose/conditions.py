"""Copies of a diagnosis set (a folder with truth.json, models/ and data/, as generate.py writes
or the blind set) read under other acquisition conditions, with the same truth: the answers
should not change.  Writes OUT/<variant>/ for each variant; score each with score.py.

usage: python3 studies/diagnose/conditions.py SET_DIR OUT_DIR

* `v128`    the records as they are, read at their own 128 Hz (no `--decimate`);
* `trunc15` the first 15 s of each record, decimated by 10 (12.8 Hz);
* `sub2`    every second sample (a 64 Hz acquisition, the same noise per sample), decimated by
            5 (12.8 Hz, each kept sample the mean of 5 readings instead of 10: sqrt(2) more noise);
* `dec5`    the records as they are, decimated by 5 (25.6 Hz);
* `notach`  a rig without a tachometer: the model files read the potentiometer and the strain
            gauge only, the records lose their `theta_dot` column; decimated by 10 (an effect
            on the tachometer alone is then not in the record, and `none` is its answer);
* `noisytach` the tachometer noisier than the rest: white noise of 3 % of each record's
            tachometer RMS added to it (Python's `random.Random(20261801)`, one stream over the
            cases in the set's order); decimated by 10.
* `nogauge` a rig without a strain gauge: the model files read the potentiometer and the
            tachometer only, the records lose their `strain` column; decimated by 10.
* `ar1all`  coloured noise added to every sensor: AR(1) with ρ = 0.9 and a stationary standard
            deviation of 1 % of each column's RMS (the same stream as `noisytach`); decimated
            by 10.
* `heavytail` heavy-tailed noise added to every sensor: Student's t with 3 degrees of freedom,
            scaled to a standard deviation of 1 % of each column's RMS (the same stream);
            decimated by 10.
* `glitch`  an acquisition glitch: on each sensor, 3 single samples at random times read
            a whole column RMS off (sign at random; the same stream); decimated by 10.

Only the standard library.  OUT_DIR must not be inside the repository (the copies of a set
that is not the project's must not be committed), must not overlap SET_DIR, and must not
already hold a variant: nothing is overwritten, and each variant is written whole or not at all.
"""
import csv
import json
import math
import os
import random
import sys

def rows_as(edit):
    """A variant's record edit from one on the data rows alone (the header kept)."""
    return lambda header, rows, rng: (header, edit(rows))


def column_of(header, column):
    """The index of `column` in a record's header."""
    if column not in header:
        raise ValueError(f"no `{column}` column in the header {','.join(header)}")
    return header.index(column)


def rms(x):
    """The root mean square of the readings `x`."""
    return math.sqrt(sum(v * v for v in x) / len(x))


def without(column):
    """Drops `column` (by its header name) from a record."""
    def edit(header, rows, rng):
        i = column_of(header, column)
        return header[:i] + header[i + 1:], [r[:i] + r[i + 1:] for r in rows]
    return edit


def noisier(column, level):
    """Adds white noise of `level` times the column's RMS to `column`, drawn from `rng`."""
    def edit(header, rows, rng):
        i = column_of(header, column)
        x = [float(r[i]) for r in rows]
        s = level * rms(x)
        return header, [r[:i] + [repr(v + rng.gauss(0.0, s))] + r[i + 1:] for r, v in zip(rows, x)]
    return edit


def coloured(columns, level, rho):
    """Adds AR(1) noise (lag-one correlation `rho`, stationary standard deviation `level` times
    the column's RMS) to each of `columns`, drawn from `rng`, started in its stationary law."""
    def edit(header, rows, rng):
        for column in columns:
            i = column_of(header, column)
            x = [float(r[i]) for r in rows]
            s = level * rms(x)
            e, noisy = rng.gauss(0.0, s), []
            for v in x:
                noisy.append(v + e)
                e = rho * e + rng.gauss(0.0, s * math.sqrt(1.0 - rho * rho))
            rows = [r[:i] + [repr(v)] + r[i + 1:] for r, v in zip(rows, noisy)]
        return header, rows
    return edit


def heavy(columns, level, dof):
    """Adds Student's t noise (`dof` degrees of freedom, scaled to a standard deviation of
    `level` times the column's RMS) to each of `columns`, drawn from `rng`."""
    def edit(header, rows, rng):
        scale = math.sqrt((dof - 2.0) / dof)
        for column in columns:
            i = column_of(header, column)
            x = [float(r[i]) for r in rows]
            s = level * rms(x) * scale
            t = [rng.gauss(0.0, 1.0) / math.sqrt(rng.gammavariate(dof / 2.0, 2.0) / dof) for _ in x]
            rows = [r[:i] + [repr(v + s * e)] + r[i + 1:] for r, v, e in zip(rows, x, t)]
        return header, rows
    return edit


def glitches(columns, count, level):
    """Moves `count` single readings of each of `columns`, at times drawn from `rng`, by `level`
    times the column's RMS (sign at random)."""
    def edit(header, rows, rng):
        for column in columns:
            i = column_of(header, column)
            x = [float(r[i]) for r in rows]
            s = level * rms(x)
            for k in rng.sample(range(len(x)), count):
                x[k] += s if rng.random() < 0.5 else -s
            rows = [r[:i] + [repr(v)] + r[i + 1:] for r, v in zip(rows, x)]
        return header, rows
    return edit


def as_is(text):
    return text


def reading(outputs):
    """The model file reading `outputs` only, in place of the three sensors."""
    full = "outputs: [Potentiometer, Tachometer, StrainGauge]"

    def edit(text):
        if full not in text:
            raise ValueError(f"the model file does not read `{full}`")
        return text.replace(full, f"outputs: [{', '.join(outputs)}]")
    return edit


# name: (CLI options, record edit (header, rows, rng) -> (header, rows), model file edit)
VARIANTS = {
    "v128": ([], rows_as(lambda rows: rows), as_is),
    "trunc15": (["--decimate", "10"], rows_as(lambda rows: [r for r in rows if float(r[0]) < 15.0]), as_is),
    "sub2": (["--decimate", "5"], rows_as(lambda rows: rows[::2]), as_is),
    "dec5": (["--decimate", "5"], rows_as(lambda rows: rows), as_is),
    "notach": (["--decimate", "10"], without("theta_dot"), reading(["Potentiometer", "StrainGauge"])),
    "noisytach": (["--decimate", "10"], noisier("theta_dot", 0.03), as_is),
    "nogauge": (["--decimate", "10"], without("strain"), reading(["Potentiometer", "Tachometer"])),
    "ar1all": (["--decimate", "10"], coloured(["theta", "theta_dot", "strain"], 0.01, 0.9), as_is),
    "heavytail": (["--decimate", "10"], heavy(["theta", "theta_dot", "strain"], 0.01, 3.0), as_is),
    "glitch": (["--decimate", "10"], glitches(["theta", "theta_dot", "strain"], 3, 1.0), as_is),
}
NOISE_SEED = 20261801


def variant(set_dir, out, args, edit_record, edit_model):
    """Writes one variant of `set_dir` to `out`: each case's model file passed through
    `edit_model`, its record through `edit_record`, and its CLI options replaced by `args`.
    Written to a sibling folder first (which main() checked is absent) and renamed when whole,
    so `out` is complete or absent."""
    partial = out + ".partial"
    os.makedirs(os.path.join(partial, "data"))
    os.makedirs(os.path.join(partial, "models"))
    with open(os.path.join(set_dir, "truth.json")) as f:
        truth = json.load(f)
    rng = random.Random(NOISE_SEED)
    for case in truth["cases"]:
        # A record or model is written inside the variant only: a path that is absolute or climbs
        # out with `..` would otherwise land anywhere, the set read included.
        for key, folder in (("data", "data"), ("model", "models")):
            target = os.path.realpath(os.path.join(partial, case[key]))
            if not inside(target, os.path.realpath(os.path.join(partial, folder))):
                sys.exit(f"{set_dir}/truth.json: case {case.get('name')!r} has {key} {case[key]!r} outside "
                         f"its {folder}/ folder; nothing of {out} is kept but {partial}")
        with open(os.path.join(set_dir, case["model"])) as f:
            model = f.read()
        try:
            model = edit_model(model)
        except ValueError as e:
            sys.exit(f"{set_dir}/{case['model']}: {e}; nothing of {out} is kept but {partial}")
        with open(os.path.join(partial, case["model"]), "w") as f:
            f.write(model)
        with open(os.path.join(set_dir, case["data"]), newline="") as f:
            rows = list(csv.reader(f))
        try:
            if not rows[1:]:
                raise ValueError("no data rows")
            header, body = edit_record(rows[0], rows[1:], rng)
        except ValueError as e:
            sys.exit(f"{set_dir}/{case['data']}: {e}; nothing of {out} is kept but {partial}")
        with open(os.path.join(partial, case["data"]), "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(header)
            w.writerows(body)
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
    for name, (args, edit_record, edit_model) in VARIANTS.items():
        variant(set_dir, outs[name], args, edit_record, edit_model)
        print(f"wrote {os.path.join(out_dir, name)} ({' '.join(args) or 'no --decimate'})")


if __name__ == "__main__":
    main()
