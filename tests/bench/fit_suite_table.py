#!/usr/bin/env python3
"""fit_suite_table.py OUT RUNS COMMAND - the fit suite's Markdown table from
the runs under OUT (tests/bench/fit_suite.sh). Run 0 of a target is the
default; runs 1.. have the learning rate moved in the 6th digit. The marks
are the suite's acceptance bounds: H <= 2 %, RMS <= 0.3 %, no
self-intersecting pair, the worst perturbed run H <= 3 % with no pair, and
at most 90 s a run."""
import datetime
import json
import os
import platform
import sys

out, runs, command = sys.argv[1], sys.argv[2], sys.argv[3]
targets, skipped = [], []
for line in open(runs):
    w = line.split()
    if len(w) >= 2 and w[1] == "skipped":
        skipped.append(w[0])
    elif len(w) == 3 and w[0] not in targets:
        targets.append(w[0])
what = {}
for line in open(os.environ.get("SUITE_LIST", "tests/bench/fit_suite.txt")):
    w = line.split("#")[0].split(None, 3)
    if len(w) == 4:
        what[w[0]] = w[3].strip()


def run(name, k):
    d = os.path.join(out, name, str(k))
    r = {"ok": False}
    try:
        r["rc"] = int(open(os.path.join(d, "rc")).read())
        m = json.load(open(os.path.join(d, "metrics.json")))
        e, rss = open(os.path.join(d, "rusage")).read().split()[-2:]
        r.update(ok=True, h=100 * m["hausdorff_rel"], rms=100 * m["rms_rel"],
                 pairs=m["tangle"]["intersecting_pairs"], it=m["iterations"], v=m["vertices"],
                 s=float(e), job=m["job_bytes"] / 1048576.0, rss=int(rss) / 1024.0)
    except (OSError, ValueError, KeyError):
        pass
    return r


def mark(ok):
    return "" if ok else " ✗"


print("# Fit suite: `largesteps fit TARGET -o DIR` with default options")
print()
print("Measured %s on %s (%s), one run per core.  " % (datetime.date.today().isoformat(), platform.node(),
                                                     platform.machine()))
print("Command: `%s`" % command.strip())
print()
print("H and RMS: dense symmetric Hausdorff distance and RMS distance over the target's bounding-box")
print("diagonal (`largesteps metrics`); pairs: self-intersecting face pairs of the result; job: the")
print("library's reservation (`ls_fit_job_bytes`); RSS: the process's peak resident memory. Perturbed: the")
print("worst of the runs whose learning rate is moved in the 6th digit (`--perturb 1..N`). ✗ marks a")
print("figure outside the acceptance bounds (H ≤ 2 %, RMS ≤ 0.3 %, 0 pairs; perturbed H ≤ 3 %, 0 pairs;")
print("≤ 90 s a run).")
print()
print("| target | what | H % | RMS % | pairs | vertices | iterations | time s | job MiB | RSS MiB | perturbed: worst H % | perturbed: most pairs |")
print("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
passed = 0
for name in targets:
    r0 = run(name, 0)
    others = []
    k = 1
    while os.path.isdir(os.path.join(out, name, str(k))):
        others.append(run(name, k))
        k += 1
    if not r0["ok"]:
        print("| %s | %s | failed (exit %s) | | | | | | | | | |" % (name, what.get(name, ""), r0.get("rc", "?")))
        continue
    good = [o for o in others if o["ok"]]
    worst_h = max([o["h"] for o in good]) if good else None
    worst_p = max([o["pairs"] for o in good]) if good else None
    ok = (r0["h"] <= 2 and r0["rms"] <= 0.3 and r0["pairs"] == 0 and r0["s"] <= 90 and
          len(good) == len(others) and (worst_h is None or (worst_h <= 3 and worst_p == 0)))
    passed += ok
    print("| %s | %s | %.2f%s | %.3f%s | %d%s | %d | %d | %.1f%s | %.1f | %.0f | %s | %s |" % (
        name, what.get(name, ""), r0["h"], mark(r0["h"] <= 2), r0["rms"], mark(r0["rms"] <= 0.3),
        r0["pairs"], mark(r0["pairs"] == 0), r0["v"], r0["it"], r0["s"], mark(r0["s"] <= 90), r0["job"], r0["rss"],
        "%.2f%s" % (worst_h, mark(worst_h <= 3)) if worst_h is not None else "-",
        "%d%s" % (worst_p, mark(worst_p == 0)) if worst_p is not None else "-"))
print()
print("%d of %d targets within every bound.%s" % (passed, len(targets),
      (" Not found (skipped): " + ", ".join(skipped) + ".") if skipped else ""))
