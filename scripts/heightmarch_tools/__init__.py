"""heightmarch's Python tools: the run's report (report.md, tables.md, report.html, plots,
measurements.csv on request), the history of recorded runs and its alerts, and the speed checks behind
scripts/compare, scripts/regress and scripts/bisect.

Modules by what they do:
- errors: the two ways a tool stops (Unusable input, exit 2; CannotWrite, exit 1);
- cli: the one top-level handler every entry point runs under (one line, never a traceback);
- readers: files checked before they are read (regular, within the memory budget) and values
  checked as they are taken (types, finite, ranges);
- writers: files written whole (atomically) and under a lock;
- escape: one escaping rule per output format (terminal, HTML, Markdown, CSV);
- spreads: medians with their min and max, per-round ratios;
- benchmark_results: Google Benchmark JSON as compare and regress read it;
- measurements: a run directory's measurements.json and the files beside it;
- report, report_page, report_plots: report.md/tables.md, report.html, plots/*.png;
- history, alerts, history_plot, record_run: the record of runs per machine;
- significance, speed_check: the statistics and the rounds of compare, regress and bisect.
"""
