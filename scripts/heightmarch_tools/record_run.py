"""Records a complete run into the history: under the history's lock, its machine's change-point
alerts are computed against the history, RUN/alerts.json and RUN/plots/history.png are written,
then whatever the caller writes from them (report.py: the report), then alerts.csv beside the
history and last the history, each read and checked before anything is written: a recording
interrupted or refused at any point before the history is written adds no row, and one
interrupted after it exits 0, saying the signal came after the record (cli.committed). A run still INCOMPLETE
(its suite did not finish, or is still writing it) is refused: only the process that owns a run
records it, after it completed (the suite runs the report with --history once it has).
"""
import os

from . import alerts, cli, history, history_plot, processes
from .errors import Unusable
from .escape import terminal
from .writers import locked, subdirectory


def record(data, run_dir, history_path, write=None):
    """Records the run of run_dir (its checked measurements.json as data) into history_path;
    write(rows, history_drawn, alerts) runs before the history is written. Returns
    (whether the history plot was drawn, the alerts as in alerts.json)."""
    if os.path.lexists(os.path.join(run_dir, "INCOMPLETE")):
        raise Unusable("%s: the run is INCOMPLETE (its suite did not finish, or is still running): it is not "
                       "recorded; without --history its report can still be written" % terminal(run_dir))
    if os.path.isdir(history_path):
        raise Unusable("--history %s: is a directory, not a history CSV file" % terminal(history_path))
    plots = subdirectory(run_dir, "plots")
    alerts_path = os.path.join(os.path.dirname(os.path.abspath(history_path)), "alerts.csv")
    with locked(history_path):
        new = history.rows_of_run(data)
        rows = history.merged(history.read(history_path), new)
        kept = history.read(alerts_path, alerts.ALERTS)  # both files read, and checked, before any is written
        found = alerts.check(data, rows, new)
        alerts.write_json(run_dir, found)
        drawn = history_plot.draw(data, rows, os.path.join(plots, "history.png"))
        if write:
            write(rows, drawn, found)
        alerts.keep(alerts_path, kept, new, found)
        # Last: the run is recorded once its rows are in the history. A signal from here on comes
        # after the record (cli.committed): the tool exits 0 saying so, never a status of a run
        # not recorded.
        with processes.signals_held():
            history.write(history_path, rows)
            cli.committed("the run was recorded in %s" % history_path)
    return drawn, found
