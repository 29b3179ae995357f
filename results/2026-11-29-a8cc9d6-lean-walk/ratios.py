"""ratios.py BENCH.json...: from heightmarch-bench runs, maxmip's and the exact reference's rays/s against
POM-32's per builtin at AVX2, by wall (manual) time and by the process's CPU time: the ratio of the
repetitions' median times, and the min-max of the per-repetition ratios (the repetitions interleaved)."""
import json
import re
import statistics
import sys

HEIGHTFIELDS = ['bricks', 'toybox', 'terrain', 'waves', 'spikes']


def main(paths):
    for path in paths:
        with open(path) as f:
            d = json.load(f)
        reps = {}
        for b in d['benchmarks']:
            if b.get('run_type') == 'iteration':
                reps.setdefault(b['run_name'], []).append(b)

        def times(pattern, key):
            names = [k for k in reps if re.search(pattern, k)]
            assert len(names) == 1, (pattern, names)
            return [b[key] for b in reps[names[0]]]

        c = d['context']
        print(f"{path}: {c['heightmarch_cpu']}, commit {c['heightmarch_commit']}, load average {c['load_avg']}")
        for key in ['real_time', 'cpu_time']:
            for what in ['maxmip', 'exact']:
                cells = []
                for hf in HEIGHTFIELDS:
                    pom = times(f'BM_Trace/heightfield:{hf}/technique:pom/layers:32/isa:avx2/', key)
                    other = times(f'BM_Trace/heightfield:{hf}/technique:maxmip/layers:1/isa:avx2/' if what == 'maxmip'
                                  else f'BM_Exact/heightfield:{hf}/', key)
                    per = [p / o for p, o in zip(pom, other)]
                    cells.append(f'{statistics.median(pom) / statistics.median(other):.2f} ({min(per):.2f}-{max(per):.2f})')
                print(f'| {what} / POM-32, {key} | ' + ' | '.join(cells) + ' |')


if __name__ == '__main__':
    main(sys.argv[1:])
