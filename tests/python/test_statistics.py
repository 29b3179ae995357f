"""spreads and significance: the figures the report, compare and regress print and judge by."""
import pytest

from heightmarch_tools import significance, spreads


def test_spreads():
    assert spreads.spread([3, 1, 2]) == (2, 1, 3)
    assert spreads.spread([]) is None
    assert spreads.per_round([4, 9, 8], [2, 3, 2]) == (3.0, 2.0, 4.0)  # per round, not median over median
    assert spreads.per_round(None, [1]) is None
    assert spreads.relative_spread((10.0, 9.0, 12.0)) == pytest.approx(0.3)


def test_benjamini_hochberg():
    # p * m / rank, then the running minimum from the largest p down
    assert significance.bh_adjusted([0.01, 0.04, 0.03, 0.5]) == pytest.approx([0.04, 0.16 / 3, 0.16 / 3, 0.5])


def test_one_sided_tests_point_the_right_way():
    slower = [1.1, 1.12, 1.09, 1.11, 1.1]
    same = [1.0, 1.01, 0.99, 1.0, 1.02]
    assert significance.welch_greater(slower, same) < 0.001 < 0.5 < significance.welch_greater(same, slower)
    assert significance.signed_rank_below_zero([-0.1] * 8) < 0.01
    assert significance.signed_rank_below_zero([0.0, 0.0]) == 1.0
    low, high = significance.proportion_interval(0, 6)
    assert low == 0.0 and 0.45 < high < 0.46  # Clopper-Pearson: 0 of 6 is 0-46%
