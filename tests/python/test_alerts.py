"""alerts: the behaviour alerts of deterministic measures, SIMD use among them."""
from heightmarch_tools import alerts, history

KEY = ("avx2", "1", "bricks", "maxmip", "", "default", "512x512", "bilinear")


def row(**measures):
    return dict({m: "" for m in history.MEASURES}, commit="abc1234", **measures)


def test_a_change_of_simd_use_is_a_behaviour_alert():
    found = alerts.behaviour_alert(KEY, row(simd_utilization="0.55"), row(simd_utilization="0.97"))
    assert found["metric"] == "simd_utilization" and found["kind"] == "behaviour"
    assert "simd_utilization 0.97 -> 0.55" in found["message"]


def test_the_same_simd_use_or_one_not_recorded_before_is_no_alert():
    assert alerts.behaviour_alert(KEY, row(simd_utilization="0.97"), row(simd_utilization="0.97")) is None
    assert alerts.behaviour_alert(KEY, row(simd_utilization="0.97"), row()) is None
