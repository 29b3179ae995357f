"""Spreads of repeated timings: the median with the min and max, and ratios taken per round (round
i of one row against round i of another: the rounds are interleaved, so they form pairs)."""
import statistics


def spread(values):
    """(median, min, max) of values, or None when there is nothing to summarise."""
    values = list(values or [])
    return (statistics.median(values), min(values), max(values)) if values else None


def per_round(a, b):
    """The spread of the per-round ratios a[i] / b[i] (None when either side is missing)."""
    if a is None or b is None:
        return None
    return spread(x / y for x, y in zip(a, b))


def relative_spread(s):
    """(max - min) / median of a spread."""
    return (s[2] - s[1]) / s[0]
