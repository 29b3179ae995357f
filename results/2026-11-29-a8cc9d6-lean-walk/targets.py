"""targets.py BENCH.json... : issue 41's rows from heightmarch-bench runs, by wall (manual) time and by the
process's CPU time. A run of the five builtins (bench-*.json): maxmip's and the exact reference's rays/s against
POM-32's at AVX2, the ratio of the repetitions' median times and the min-max of the per-repetition ratios (the
repetitions interleaved). A P2 run at 2048 x 2048 (p2-*.json): per builtin, maxmip's Mrays/s against the other
technique's, median (min-max) of the repetitions; P2 passes where maxmip is faster with the spreads apart."""
import json
import re
import statistics
import sys

HEIGHTFIELDS = ['bricks', 'toybox', 'terrain', 'waves', 'spikes']
TIMES = ['real_time', 'cpu_time']


def pom_ratios(reps):
    def times(pattern, key):
        names = [k for k in reps if re.search(pattern, k)]
        assert len(names) == 1, (pattern, names)
        return [b[key] for b in reps[names[0]]]

    for key in TIMES:
        for what in ['maxmip', 'exact']:
            cells = []
            for hf in HEIGHTFIELDS:
                pom = times(f'BM_Trace/heightfield:{hf}/technique:pom/layers:32/isa:avx2/', key)
                other = times(f'BM_Trace/heightfield:{hf}/technique:maxmip/layers:1/isa:avx2/' if what == 'maxmip'
                              else f'BM_Exact/heightfield:{hf}/', key)
                per = [p / o for p, o in zip(pom, other)]
                cells.append(f'{statistics.median(pom) / statistics.median(other):.2f} ({min(per):.2f}-{max(per):.2f})')
            print(f'| {what} / POM-32, {key} | ' + ' | '.join(cells) + ' |')


def p2(reps):
    rows = {}
    for name, bs in reps.items():
        fields = dict(p.split(':', 1) for p in name.split('/')[1:] if ':' in p)
        rows.setdefault(fields['heightfield'], {})[f"{fields['technique']} {fields['layers']}"] = bs
    for hf, techniques in rows.items():
        for key in TIMES:
            cells = {}
            for t, bs in techniques.items():
                rays = bs[0]['rays_per_second'] * bs[0]['real_time']  # rays a repetition, in the times' unit
                mrays = [rays / b[key] / 1e6 for b in bs]
                cells[t] = (statistics.median(mrays), min(mrays), max(mrays), bs[0]['uv_error_p99'])
            m = cells.pop('maxmip 1')
            (other, o), = cells.items()
            verdict = 'faster' if m[1] > o[2] else 'slower' if m[2] < o[1] else 'not distinguishable'
            print(f'| {hf} | {key} | maxmip {m[0]:.1f} ({m[1]:.1f}-{m[2]:.1f}), p99 {m[3]:.2g} | '
                  f'{other} {o[0]:.1f} ({o[1]:.1f}-{o[2]:.1f}), p99 {o[3]:.2g} | {verdict} |')


def main(paths):
    for path in paths:
        with open(path) as f:
            d = json.load(f)
        reps = {}
        for b in d['benchmarks']:
            if b.get('run_type') == 'iteration':
                reps.setdefault(b['run_name'], []).append(b)
        c = d['context']
        print(f"{path}: {c['heightmarch_cpu']}, commit {c['heightmarch_commit']}, load average {c['load_avg']}")
        large = c['heightmarch_depth_map'] != '512x512'
        (p2 if large else pom_ratios)(reps)


if __name__ == '__main__':
    main(sys.argv[1:])
