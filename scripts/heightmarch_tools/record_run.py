"""Records a run: its rows appended to the history, its machine's change-point alerts written to
RUN/alerts.json and kept in alerts.csv beside the history, RUN/plots/history.png drawn.
report.py calls it for a run recorded with --history."""
import os

from . import alerts, history, history_plot
from .readers import read_json


def record(run_dir, history_path):
    """(whether the history plot was drawn, the alerts as in alerts.json)."""
    data = read_json(os.path.join(run_dir, "measurements.json"))
    rows, new = history.append(history_path, data)
    found = alerts.record(data, rows, new, run_dir,
                          os.path.join(os.path.dirname(os.path.abspath(history_path)), "alerts.csv"))
    os.makedirs(os.path.join(run_dir, "plots"), exist_ok=True)
    return history_plot.draw(data, rows, os.path.join(run_dir, "plots", "history.png")), found
