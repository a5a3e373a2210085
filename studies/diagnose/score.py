#!/usr/bin/env python3
"""Score `memid diagnose` on a set written by generate.py (or any set with the same truth.json).

usage (from the project root, after `cargo build --release -p memid`):
  python3 studies/diagnose/score.py DIR [--only-family X] [--limit N] [--jobs 1]
                                        [--out report.md] [--results results.json]
                                        [--memid target/release/memid] [--timeout 900] [--keep DIR]

Per case it runs
  memid diagnose --model M --data D --free F <args> --json out.json -o augmented.ron
A case is right when the named effect is in its `accept` list and, for a sensor effect
(output_offset, sensor_scale, sensor_drift, sensor_quantization) in families A and D, the label
names the truly affected sensor, e.g. `output_offset(theta_dot)`; a structure's mode named as an
appendage at a coordinate, `unmodeled_mode(q2, 20.01 Hz)`, must be at the truth's coordinate
(counted with the wrong sensors, `*`).  For family D, diagnose runs a
second time on the augmented model (-o) with the same data and free parameters; the second answer
is right when it is the other effect (in that form's own accept list, as family A scores the form
alone), and "both found" counts cases whose two answers name both.
A crash, a missing/invalid JSON or a timeout counts as "error".
"""
import argparse
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor

SENSOR_EFFECTS = {"output_offset", "sensor_scale", "sensor_drift", "sensor_quantization"}
ALIASES = [{"amplifier_saturation", "voltage_saturation"}]


def group(name):
    for g in ALIASES:
        if name in g:
            return min(g)
    return name
STRENGTHS = ["weak", "medium", "strong", "-"]


def diagnose(memid, model, data, free, args, workdir, tag, timeout):
    out = os.path.join(workdir, tag + ".json")
    aug = os.path.join(workdir, tag + ".ron")
    cmd = [memid, "diagnose", "--model", model, "--data", data, "--free", free, *args,
           "--json", out, "-o", aug]
    t0 = time.time()
    res = {"effect": "error", "label": None, "seconds": None, "augmented": None, "detail": ""}
    try:
        r = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
        res["seconds"] = time.time() - t0
        if r.returncode != 0:
            res["detail"] = f"exit {r.returncode}: " + (r.stderr.strip().splitlines() or [""])[-1][:300]
        elif not os.path.exists(out):
            res["detail"] = "no JSON written"
        else:
            d = json.load(open(out))
            res["effect"] = d.get("effect") or "?"
            res["label"] = d.get("label")
            res["parameters"] = d.get("parameters")
            res["baseline_error"] = d.get("baseline_error")
            res["augmented_error"] = d.get("augmented_error")
            cands = d.get("candidates") or []
            res["top_candidates"] = [{"label": c.get("label") or c.get("effect"), "delta_bic": c.get("delta_bic")}
                                     for c in cands[:3]]
            if os.path.exists(aug):
                res["augmented"] = aug
    except subprocess.TimeoutExpired:
        res["seconds"] = time.time() - t0
        res["detail"] = f"timeout after {timeout} s"
    except (OSError, ValueError) as e:
        res["seconds"] = time.time() - t0
        res["detail"] = f"{type(e).__name__}: {e}"
    return res


def sensors_for(case, effect_name):
    """The sensors truly affected by the case's effects whose catalog name is effect_name."""
    return [e["sensor"] for e in case["truth"].get("effects", [])
            if e.get("effect") == effect_name and "sensor" in e]


def sensor_ok(case, named, label):
    if case["family"] in ("A", "D") and named == "unmodeled_mode":
        return floor_ok(case, label)
    if case["family"] not in ("A", "D") or named not in SENSOR_EFFECTS:
        return True
    sens = sensors_for(case, named)
    if not sens:
        return True
    return any(f"({s})" in (label or "") for s in sens)


def floor_ok(case, label):
    """A structure's mode named as an appendage at a coordinate (`unmodeled_mode(q2, 20.01 Hz)`)
    must be at the coordinate the truth's appendage hangs on; a mode without one in its label
    (a ringing in the outputs, or the slewing rig's coupling) makes no such claim."""
    m = re.match(r"unmodeled_mode\((q\d+), ", label or "")
    floors = [e["coordinate"] for e in case["truth"].get("effects", [])
              if e.get("effect") == "unmodeled_mode" and "coordinate" in e]
    return m is None or not floors or m.group(1) in floors


def form_accepts(case):
    """Each form's own accept list for a two-effect case of generate.py (`forms`), or None for
    a set without forms (the blind set): a stand-in family A accepts for a form alone (a soft
    voltage saturation answered as the cubic stiffness it equals at small demand) is accepted
    for that form in a chain too."""
    forms = case.get("forms") or []
    if len(forms) != 2:
        return None
    here = os.path.dirname(os.path.abspath(__file__))
    if here not in sys.path:
        sys.path.insert(0, here)
    try:
        from generate import FORM_EFFECT
    except ImportError:
        return None
    if not all(f in FORM_EFFECT for f in forms):
        return None
    return [list(FORM_EFFECT[f][1]) for f in forms]


def run_case(case, set_dir, opt, workdir):
    model = os.path.join(set_dir, case["model"])
    data = os.path.join(set_dir, case["data"])
    args = case.get("args", [])
    r1 = diagnose(opt.memid, model, data, case["free"], args, workdir, case["name"], opt.timeout)
    rec = {"name": case["name"], "family": case["family"], "strength": case.get("strength", "-"),
           "expected": case["effect"], "accept": case["accept"], "rate": "12.8 Hz" if args else "128 Hz",
           "first": r1, "forms": case.get("forms")}
    if case["family"] == "B":
        rec["null_kind"] = case["truth"].get("null_kind", "?")
    effects = case.get("truth", {}).get("effects") or [{}]
    if "resonance_nats" in effects[0]:  # a forced appendage of studies/structure (its generator)
        rec["resonance_nats"] = effects[0]["resonance_nats"]
    named, label = r1["effect"], r1["label"]
    rec["right"] = named in case["accept"] and sensor_ok(case, named, label)
    rec["wrong_sensor"] = named in case["accept"] and not sensor_ok(case, named, label)
    if case["family"] == "D":
        pair = [case["effect"], case.get("second")]
        rec["second_expected"] = None
        rec["second_right"] = False
        rec["both_found"] = False
        rec["pair"] = pair
        if rec["right"] and r1.get("augmented"):
            each = form_accepts(case)
            if each:
                # each form's own accept list, as family A scores it alone: the first answer
                # stands for the form whose list holds it, the second must be in the other's
                first = 0 if named in each[0] else 1
                other_accept = each[1 - first]
                other = pair[1 - first]
            else:
                # the other effect: the pair member not in the first answer's group (aliases such
                # as amplifier/voltage saturation form one group)
                other = [p for p in pair if group(p) != group(named)]
                other = other[0] if other else pair[1]
                other_accept = [e for e in case["accept"] if group(e) == group(other)]
            rec["second_expected"] = other
            r2 = diagnose(opt.memid, r1["augmented"], data, case["free"], args, workdir,
                          case["name"] + ".2", opt.timeout)
            rec["second"] = r2
            rec["second_right"] = (r2["effect"] in other_accept
                                   and sensor_ok(case, r2["effect"], r2["label"]))
            rec["both_found"] = rec["second_right"]
        else:
            rec["second"] = None
    return rec


def fmt_named(r):
    if r is None:
        return "-"
    return r["label"] or r["effect"]


def report(recs, set_dir, wall):
    L = []
    P = L.append
    P(f"# `memid diagnose` on {os.path.basename(os.path.normpath(set_dir))}")
    P("")
    P(f"{len(recs)} cases, {wall:.0f} s wall time.")
    P("")
    # per family and strength
    P("## Right answers per family and strength")
    P("")
    P("| family | weak | medium | strong | - | total |")
    P("|---|---|---|---|---|---|")
    for fam in sorted({r["family"] for r in recs}):
        row = [fam]
        tot = [0, 0]
        for s in STRENGTHS:
            rs = [r for r in recs if r["family"] == fam and r["strength"] == s]
            k = sum(r["right"] for r in rs)
            tot[0] += k
            tot[1] += len(rs)
            row.append(f"{k}/{len(rs)}" if rs else "·")
        row.append(f"{tot[0]}/{tot[1]} ({100 * tot[0] / max(tot[1], 1):.0f} %)")
        P("| " + " | ".join(row) + " |")
    P("")
    # confusion per strength for A
    A = [r for r in recs if r["family"] == "A"]
    if A:
        P("## Family A: confusion (true effect → named effect), per strength")
        P("")
        P("`*` marks a sensor effect named with the wrong sensor, or an appendage named at the wrong floor.")
        for s in ("weak", "medium", "strong"):
            rs = [r for r in A if r["strength"] == s]
            if not rs:
                continue
            trues = sorted({r["expected"] for r in rs})
            named = sorted({(r["first"]["effect"] + ("*" if r["wrong_sensor"] else "")) for r in rs})
            P("")
            P(f"### {s} ({sum(r['right'] for r in rs)}/{len(rs)} right)")
            P("")
            P("| true \\ named | " + " | ".join(named) + " |")
            P("|---|" + "---|" * len(named))
            for t in trues:
                cells = []
                for n in named:
                    k = sum(1 for r in rs if r["expected"] == t
                            and (r["first"]["effect"] + ("*" if r["wrong_sensor"] else "")) == n)
                    cells.append(str(k) if k else "·")
                P(f"| {t} | " + " | ".join(cells) + " |")
        P("")
        P("### Family A per form")
        P("")
        P("| form | right | named |")
        P("|---|---|---|")
        forms = sorted({r["forms"][0] for r in A if r.get("forms")})
        for f in forms:
            rs = [r for r in A if r.get("forms") and r["forms"][0] == f]
            names = {}
            for r in rs:
                names[fmt_named(r["first"])] = names.get(fmt_named(r["first"]), 0) + 1
            P(f"| {f} | {sum(r['right'] for r in rs)}/{len(rs)} | "
              + ", ".join(f"{k} ×{v}" for k, v in sorted(names.items(), key=lambda x: -x[1])) + " |")
        P("")
        seen = [r for r in A if "resonance_nats" in r]
        if seen:
            # The generator's bound on how far each appendage shows as a mode of its own (nats):
            # below the 10-nat threshold its resonance is under the noise, and what the record
            # shows of it is an added mass.
            P("### Appendages by how far the record shows them as a mode")
            P("")
            P("| resonance_nats | right | cases (strength, nats, named) |")
            P("|---|---|---|")
            for title, rs in (("≥ 10", [r for r in seen if r["resonance_nats"] >= 10.0]),
                              ("< 10", [r for r in seen if r["resonance_nats"] < 10.0])):
                cases = "; ".join(f"{r['strength']} {r['resonance_nats']:.1f} {fmt_named(r['first'])}" for r in rs)
                P(f"| {title} | {sum(r['right'] for r in rs)}/{len(rs)} | {cases or '—'} |")
            P("")
    B = [r for r in recs if r["family"] == "B"]
    if B:
        P("## Family B: null false alarms")
        P("")
        fa = [r for r in B if not r["right"]]
        P(f"False-alarm rate {len(fa)}/{len(B)} ({100 * len(fa) / len(B):.0f} %); errors count as false alarms.")
        P("")
        P("| split | false alarms | named |")
        P("|---|---|---|")
        for rate in ("12.8 Hz", "128 Hz"):
            rs = [r for r in B if r["rate"] == rate]
            if rs:
                bad = [fmt_named(r["first"]) for r in rs if not r["right"]]
                P(f"| {rate} | {len(bad)}/{len(rs)} | {', '.join(sorted(bad)) or '—'} |")
        for nk in sorted({r["null_kind"] for r in B}):
            rs = [r for r in B if r["null_kind"] == nk]
            bad = [fmt_named(r["first"]) for r in rs if not r["right"]]
            P(f"| {nk} | {len(bad)}/{len(rs)} | {', '.join(sorted(bad)) or '—'} |")
        P("")
    C = [r for r in recs if r["family"] == "C"]
    if C:
        wrong = [r for r in C if not r["right"]]
        P("## Family C: physics outside the catalog")
        P("")
        P(f"Wrong-name rate {len(wrong)}/{len(C)} ({100 * len(wrong) / len(C):.0f} %) (a name outside `accept`).")
        P("")
        P("| case | accept | named |")
        P("|---|---|---|")
        for r in C:
            P(f"| {r['name']} | {', '.join(r['accept'])} | {fmt_named(r['first'])}{'' if r['right'] else ' ✗'} |")
        P("")
    D = [r for r in recs if r["family"] == "D"]
    if D:
        P("## Family D: two effects")
        P("")
        both = sum(r["both_found"] for r in D)
        P(f"First answer right {sum(r['right'] for r in D)}/{len(D)}; both found {both}/{len(D)} "
          f"({100 * both / len(D):.0f} %).")
        P("")
        P("| case | expected | first | second |")
        P("|---|---|---|---|")
        for r in D:
            P(f"| {r['name']} | {' + '.join(r.get('pair') or r['accept'][:2])} | {fmt_named(r['first'])} | "
              f"{fmt_named(r.get('second'))}{' ✓' if r['both_found'] else ''} |")
        P("")
    P("## Runtime per diagnosis")
    P("")
    P("| rate | runs | median s | max s |")
    P("|---|---|---|---|")
    for rate in ("12.8 Hz", "128 Hz"):
        secs = []
        for r in recs:
            if r["rate"] != rate:
                continue
            for run in (r["first"], r.get("second")):
                if run and run.get("seconds") is not None:
                    secs.append(run["seconds"])
        if secs:
            P(f"| {rate} | {len(secs)} | {statistics.median(secs):.1f} | {max(secs):.1f} |")
    errs = [r for r in recs if r["first"]["effect"] == "error" or (r.get("second") or {}).get("effect") == "error"]
    if errs:
        P("")
        P("## Errors")
        P("")
        for r in errs:
            for run in (r["first"], r.get("second")):
                if run and run["effect"] == "error":
                    P(f"- {r['name']}: {run['detail']}")
    P("")
    return "\n".join(L)


def main():
    ap = argparse.ArgumentParser(description="score memid diagnose on a generated set")
    ap.add_argument("set_dir")
    ap.add_argument("--only-family", default=None, help="e.g. A or AB")
    ap.add_argument("--limit", type=int, default=None)
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--out", default=None, help="write the markdown report here")
    ap.add_argument("--results", default=None, help="write per-case results as JSON here")
    ap.add_argument("--memid", default="target/release/memid")
    ap.add_argument("--timeout", type=float, default=900.0)
    ap.add_argument("--keep", default=None,
                    help="keep each diagnosis's JSON and augmented model in this directory")
    opt = ap.parse_args()
    set_dir = os.path.abspath(opt.set_dir)
    if not os.path.exists(opt.memid):
        sys.exit(f"{opt.memid} not found: run from the project root after cargo build --release -p memid")
    cases = json.load(open(os.path.join(set_dir, "truth.json")))["cases"]
    if opt.only_family:
        cases = [c for c in cases if c["family"] in opt.only_family]
    if opt.limit:
        cases = cases[:opt.limit]
    t0 = time.time()
    recs = []
    with tempfile.TemporaryDirectory() as tmp:
        work = opt.keep or tmp
        os.makedirs(work, exist_ok=True)
        def one(c):
            try:
                return run_case(c, set_dir, opt, work)
            except Exception as e:              # never let one case stop the study
                return {"name": c["name"], "family": c["family"], "strength": c.get("strength", "-"),
                        "expected": c["effect"], "accept": c["accept"], "rate": "12.8 Hz" if c.get("args") else "128 Hz",
                        "first": {"effect": "error", "label": None, "seconds": None, "detail": repr(e)},
                        "right": False, "wrong_sensor": False, "both_found": False, "second": None,
                        "null_kind": c["truth"].get("null_kind", "?"), "forms": c.get("forms")}

        with ThreadPoolExecutor(max_workers=max(1, opt.jobs)) as ex:
            for i, rec in enumerate(ex.map(one, cases)):
                recs.append(rec)
                extra = ""
                if rec["family"] == "D":
                    extra = f" then {fmt_named(rec.get('second'))}{' (both)' if rec['both_found'] else ''}"
                s = rec["first"].get("seconds")
                print(f"[{i + 1}/{len(cases)}] {rec['name']:<44} {'ok ' if rec['right'] else 'XX '} "
                      f"{fmt_named(rec['first'])}{extra}  ({rec['rate']}, {s if s is None else round(s, 1)} s)",
                      flush=True)
    md = report(recs, set_dir, time.time() - t0)
    print()
    print(md)
    if opt.out:
        with open(opt.out, "w") as fh:
            fh.write(md)
    if opt.results:
        for r in recs:
            for k in ("first", "second"):
                if r.get(k):
                    r[k].pop("augmented", None)
        with open(opt.results, "w") as fh:
            json.dump(recs, fh, indent=1)


if __name__ == "__main__":
    main()
