#!/usr/bin/env python3
"""Tables benchmarks/alternate_benchmarks.sh's output: per benchmark, each build's median and
range over the rounds, and new/base (speed: items per second, or 1/time)."""
import collections
import glob
import json
import statistics
import sys
rows = collections.defaultdict(lambda: {'base': [], 'new': []})
for f in sorted(glob.glob(sys.argv[1] + '/*.json')):
    b, bench, _round, _ = f.split('/')[-1].split('.')
    try:
        d = json.load(open(f))
    except Exception as e:
        print('bad', f, e); continue
    for x in d['benchmarks']:
        if x.get('run_type') == 'aggregate': continue
        v = x.get('items_per_second')
        key = (bench, x['name'])
        if v is None:
            v = 1.0 / x['real_time']  # faster = bigger
            key = (bench, x['name'] + ' (1/time)')
        rows[key][b].append(v)
        for k, val in x.items():
            if k.startswith('ratio') or k.endswith('_ratio') or k in ('overhead', 'plain_vs_minimal'):
                rows[(bench, x['name'] + ' :' + k)][b].append(val)
print('| benchmark | base median [min–max] | new median [min–max] | new/base |')
print('|---|---|---|---|')
for (bench, name), v in sorted(rows.items()):
    if not v['base'] or not v['new']: continue
    mb, mn = statistics.median(v['base']), statistics.median(v['new'])
    print(f"| {bench} {name} | {mb:.4g} [{min(v['base']):.4g}–{max(v['base']):.4g}] | {mn:.4g} [{min(v['new']):.4g}–{max(v['new']):.4g}] | {mn/mb:.3f} |")
