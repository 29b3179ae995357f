import json, sys, statistics, re
d = json.load(open(sys.argv[1]))
rows = {}
for b in d['benchmarks']:
    if b.get('run_type') != 'iteration': continue
    rows.setdefault(b['run_name'], []).append(b)
def med(pat, key):
    ks = [k for k in rows if re.search(pat, k)]
    assert len(ks) == 1, (pat, ks)
    return statistics.median(b[key] for b in rows[ks[0]])
hfs = ['bricks', 'toybox', 'terrain', 'waves', 'spikes']
isas = ['sse4.2', 'avx2', 'avx512']
def trace(hf, tech, isa, layers=32):
    return f'BM_Trace/heightfield:{hf}/technique:{tech}/layers:{layers}/isa:{isa}/'
out = []
for tech in ['pom', 'relief', 'steep']:
    cells = []
    for hf in hfs:
        g = med(f'BM_GLSL/heightfield:{hf}/technique:{tech}/layers:32/', 'rays_per_second')
        cells.append(' / '.join(f"{med(trace(hf, tech, i), 'rays_per_second') / g:.1f}" for i in isas))
    out.append(f'| {tech.upper() if tech=="pom" else tech}-32 x llvmpipe, sse4.2 / avx2 / avx512 | ' + ' | '.join(cells) + ' | 3 / 5 / 8 |')
cells = []
for hf in hfs:
    cells.append(' / '.join(f"{100 * med(trace(hf, 'pom', i), 'samples_per_second') / med(f'BM_ComputeCeiling/heightfield:{hf}/layers:32/isa:{i}/', 'samples_per_second'):.0f}" for i in isas))
out.append('| POM-32 samples/s, % of BM_ComputeCeiling, sse4.2 / avx2 / avx512 | ' + ' | '.join(cells) + ' | 60 |')
out.append('| maxmip / POM-32 rays/s, avx512 | ' + ' | '.join(f"{med(trace(hf, 'maxmip', 'avx512', 1), 'rays_per_second') / med(trace(hf, 'pom', 'avx512'), 'rays_per_second'):.2f}" for hf in hfs) + ' | 0.5 |')
out.append('| exact / POM-32 rays/s, avx512 | ' + ' | '.join(f"{med(f'BM_Exact/heightfield:{hf}/', 'rays_per_second') / med(trace(hf, 'pom', 'avx512'), 'rays_per_second'):.2f}" for hf in hfs) + ' | 0.3 |')
out.append('| maxmip SIMD use, sse4.2 / avx2 / avx512 | ' + ' | '.join(' / '.join(f"{100 * med(trace(hf, 'maxmip', i, 1), 'simd_utilization'):.0f}%" for i in isas) for hf in hfs) + ' | 85% |')
out.append('| maxmip Mrays/s, sse4.2 / avx2 / avx512 | ' + ' | '.join(' / '.join(f"{med(trace(hf, 'maxmip', i, 1), 'rays_per_second')/1e6:.1f}" for i in isas) for hf in hfs) + ' | |')
print('\n'.join(out))
