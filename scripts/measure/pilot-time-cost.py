#!/usr/bin/env python3
"""vcm's pilot: photon mapping's figure over the best other candidate, by the cost model and by
the pilot passes' measured times, and each candidate's measured time over its modelled cost
relative to the best's. Reads pilot logs written with SPPM_GPU_PILOT_LOG=1 (SPPM_GPU_PILOT_ALL=1
for every candidate), e.g.

    SPPM_GPU_PILOT_ALL=1 SPPM_GPU_PILOT_LOG=1 sppm-gpu scenes/mitsuba/lens.xml --method vcm \
        --time-limit 30 -o o.exr 2> lens.log      # stopped once the pilot's note is printed
    python3 scripts/measure/pilot-time-cost.py lens.log

Feeds docs/journal/session-36.md "vcm on the scenes the issue does not name"."""
import sys, re, statistics
for path in sys.argv[1:]:
    names=[]; cand={}; times={}; pm_t=[]
    for line in open(path):
        m = re.match(r"pilot candidate (\S+) (\S+) (\S+)", line)
        if m:
            cand[m[1]] = (float(m[2]), float(m[3]))
            if m[1] != 'sppm': names.append(m[1])
        m = re.match(r"pilot pass (\d+) ([0-9.]+)", line)
        if m: times.setdefault(int(m[1]), []).append(float(m[2]))
        m = re.match(r"pilot sppm pass ([0-9.]+)", line)
        if m: pm_t.append(float(m[1]))
    if 'sppm' not in cand: print(path.split('/')[-1], 'no pm'); continue
    ks = sorted(times)
    t = {names[i]: statistics.mean(times[k]) for i, k in enumerate(ks) if i < len(names)}
    t['sppm'] = statistics.mean(pm_t)
    fc = {n: cand[n][0]*cand[n][1] for n in cand}
    ft = {n: cand[n][0]*t[n] for n in cand if n in t}
    oc = min(v for n,v in fc.items() if n!='sppm'); ot = min(v for n,v in ft.items() if n!='sppm')
    bc = min((v,n) for n,v in fc.items() if n!='sppm')[1]; bt = min((v,n) for n,v in ft.items() if n!='sppm')[1]
    ratio_cost = {n: round(t[n]/t[bc] / (cand[n][1]/cand[bc][1]),2) for n in t}
    print(f"{path.split('/')[-1]:14} pm/best by cost {fc['sppm']/oc:.2f} ({bc}), by time {ft['sppm']/ot:.2f} ({bt}); time/cost vs {bc}: {ratio_cost}")

# vcm's own candidates (photon mapping left out): the best by the cost model and by measured
# time, each figure over its margin (the denser form 0.9, no light subpaths 1.1).
for path in sys.argv[1:]:
    names, cand, times = [], {}, {}
    for line in open(path):
        m = re.match(r"pilot candidate (\S+) (\S+) (\S+)", line)
        if m and m[1] != 'sppm':
            cand[m[1]] = (float(m[2]), float(m[3]))
            names.append(m[1])
        m = re.match(r"pilot pass (\d+) ([0-9.]+)", line)
        if m:
            times.setdefault(int(m[1]), []).append(float(m[2]))
    t = {names[i]: statistics.mean(times[k]) for i, k in enumerate(sorted(times)) if i < len(names)}
    margin = lambda n: 0.9 if '@' in n else (1.1 if n == 'none' else 1.0)
    fc = {n: cand[n][0] * cand[n][1] / margin(n) for n in cand}
    ft = {n: cand[n][0] * t[n] / margin(n) for n in cand if n in t}
    if not ft:
        continue
    bc, bt = min(fc, key=fc.get), min(ft, key=ft.get)
    order = sorted(ft, key=ft.get)
    print(f"{path.split('/')[-1]:16} best by cost {bc:6} by time {bt:6}; by time: " + " ".join(f"{n} {ft[n] / ft[bt]:.2f}" for n in order))
