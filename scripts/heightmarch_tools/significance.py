"""Significance over many benchmarks at once: one-sided tests of "NEW is slower" and the
Benjamini-Hochberg correction that keeps the share of false alarms among a run's flags at the
level asked for (and, when nothing changed at all, the chance of any flag)."""
import math
import statistics

from scipy import stats


def welch_greater(new, old):
    """p of Welch's t-test that mean(new) > mean(old) (log times: NEW slower); samples of >= 2."""
    va, vb = statistics.variance(new), statistics.variance(old)
    se2 = va / len(new) + vb / len(old)
    diff = statistics.mean(new) - statistics.mean(old)
    if se2 == 0:  # identical repetitions on both sides: only the difference itself can tell
        return 0.0 if diff > 0 else 1.0
    df = se2 ** 2 / ((va / len(new)) ** 2 / (len(new) - 1) + (vb / len(old)) ** 2 / (len(old) - 1))
    return float(stats.t.sf(diff / math.sqrt(se2), df))


def signed_rank_below_zero(values):
    """p of Wilcoxon's signed-rank test that values (paired differences) lie below 0; 1 for fewer
    than 2 values or all zero."""
    if len(values) < 2 or not any(values):
        return 1.0
    return float(stats.wilcoxon(values, alternative="less").pvalue)


def rank_greater(group, rest):
    """p of the Mann-Whitney U test that the values of group lie above those of rest."""
    return float(stats.mannwhitneyu(group, rest, alternative="greater").pvalue)


def bh_adjusted(pvalues):
    """Benjamini-Hochberg adjusted p-values (q-values): a test is a discovery at level Q when its
    q-value is at most Q."""
    m = len(pvalues)
    order = sorted(range(m), key=lambda i: pvalues[i])
    q, running = [1.0] * m, 1.0
    for rank in range(m, 0, -1):
        i = order[rank - 1]
        running = min(running, pvalues[i] * m / rank)
        q[i] = running
    return q


def proportion_interval(successes, n, level=0.95):
    """Clopper-Pearson interval of a rate measured as successes out of n trials: (low, high)."""
    tail = (1 - level) / 2
    low = float(stats.beta.ppf(tail, successes, n - successes + 1)) if successes > 0 else 0.0
    high = float(stats.beta.ppf(1 - tail, successes + 1, n - successes)) if successes < n else 1.0
    return low, high
