"""p2.py P2.json...: P2's speed check at 2048 x 2048 from heightmarch-bench runs: per builtin, maxmip's
Mrays/s against the other technique's in the same run, median (min-max) of the repetitions, by wall
(manual) time and by the process's CPU time; P2 passes where maxmip is faster with the spreads apart."""
import json
import statistics
import sys


def main(paths):
    for path in paths:
        with open(path) as f:
            d = json.load(f)
        reps = {}
        for b in d['benchmarks']:
            if b.get('run_type') == 'iteration':
                reps.setdefault(b['run_name'], []).append(b)
        rows = {}
        for name, bs in reps.items():
            fields = dict(p.split(':', 1) for p in name.split('/')[1:] if ':' in p)
            rows.setdefault(fields['heightfield'], {})[f"{fields['technique']} {fields['layers']}"] = bs
        print(f"{path}: load average {d['context']['load_avg']}")
        for hf, techniques in rows.items():
            for key in ['real_time', 'cpu_time']:
                cells = {}
                for t, bs in techniques.items():
                    rays = bs[0]['rays_per_second'] * bs[0]['real_time']  # rays a repetition (time in ms units cancel)
                    mrays = [rays / b[key] / 1e6 for b in bs]
                    cells[t] = (statistics.median(mrays), min(mrays), max(mrays), bs[0]['uv_error_p99'])
                m = cells.pop('maxmip 1')
                (other, o), = cells.items()
                verdict = 'faster' if m[1] > o[2] else 'slower' if m[2] < o[1] else 'not distinguishable'
                print(f'| {hf} | {key} | maxmip {m[0]:.1f} ({m[1]:.1f}-{m[2]:.1f}), p99 {m[3]:.2g} | '
                      f'{other} {o[0]:.1f} ({o[1]:.1f}-{o[2]:.1f}), p99 {o[3]:.2g} | {verdict} |')


if __name__ == '__main__':
    main(sys.argv[1:])
