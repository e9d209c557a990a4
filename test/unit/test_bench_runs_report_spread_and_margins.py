"""``python -m bench --runs N``'s report (bench/runs.py, bench/report.py): each targeted row's
min / median / max over the runs and its margin in the worst run, pass only if every run
passed — a row that met its target on the median but missed it once fails. No benchmark runs
here: the rows are made by hand."""
import json

import numpy as np

import pytest

from bench import runs
from bench.report import FAIL, NOT_RUN, PASS, REPORT, Bound, Row, at_least, at_most, not_run, write

RTT = "controller backend: servo_j round trip p99"


def rtt_row(p99_ms: float) -> Row:
    """A round-trip row as bench.floor_targets makes it: p99 ≤ 1 ms."""
    return Row("Tails", RTT, f"p99 {p99_ms:.3f} ms", "≤ 1 ms",
               PASS if p99_ms <= 1.0 else FAIL, "" if p99_ms <= 1.0 else "the lock",
               bounds=at_most(p99_ms, 1.0, "ms", "p99"))


def test_a_bound_s_margin_is_the_room_left_to_its_limit_on_either_side():
    assert Bound(0.8, 1.0, "ms").margin == pytest.approx(0.2)
    assert Bound(1.5, 1.0, "ms").margin == pytest.approx(-0.5) and not Bound(1.5, 1.0).met
    assert Bound(160.0, 150.0, at_most=False).margin == pytest.approx(10.0)
    assert Bound(1.0, 1.0).met                       # at the limit is within it
    assert at_most(None, 1.0) == [] and at_least(None, 1.0) == []


def test_three_runs_give_min_median_max_and_the_worst_run_s_margin():
    (row,) = runs.combine([[rtt_row(0.61)], [rtt_row(0.95)], [rtt_row(0.72)]])
    (s,) = row.data["spread"]
    assert (s["min"], s["median"], s["max"]) == (0.61, 0.72, 0.95)
    assert s["worst_margin"] == pytest.approx(0.05) and s["limit"] == 1.0
    assert row.status == PASS and row.data["met_in"] == 3
    assert row.value == "p99 0.61 / 0.72 / 0.95 ms"
    assert runs.margin_text(s) == "+0.05 ms"


def test_one_miss_in_three_fails_the_row_though_its_median_is_within():
    (row,) = runs.combine([[rtt_row(0.61)], [rtt_row(1.503)], [rtt_row(0.72)]])
    (s,) = row.data["spread"]
    assert s["median"] == 0.72 <= 1.0                  # the median alone would pass
    assert row.status == FAIL and row.data["met_in"] == 2
    assert runs.margin_text(s) == "−0.503 ms"
    assert row.note == "run 2: the lock"               # the failing run's explanation


def test_a_row_missing_or_not_run_in_one_run_is_not_a_pass():
    (row,) = runs.combine([[rtt_row(0.6)], [], [rtt_row(0.7)]])
    assert row.status == NOT_RUN and "run 2: no such row" in row.note
    assert row.data["spread"][0]["runs"] == 2 and row.value.endswith("(2 of 3 runs)")
    (row,) = runs.combine([[rtt_row(0.6)], [not_run("Tails", RTT, "≤ 1 ms", "no emulator")]])
    assert row.status == NOT_RUN and "run 2: no emulator" in row.note
    (row,) = runs.combine([[rtt_row(1.2)], [not_run("Tails", RTT, "≤ 1 ms", "no emulator")]])
    assert row.status == FAIL


def test_rows_with_several_bounds_and_rows_without_any():
    def ik(median_us, ratio):
        bounds = at_most(median_us, 50.0, "µs", "median") + at_least(ratio, 3.0, "×", "vs KDL")
        ok = all(b.met for b in bounds)
        return Row("IK", "zu5: median time", "…", "median ≤ 50 µs; ≥ 3× faster",
                   PASS if ok else FAIL, bounds=bounds)

    (row,) = runs.combine([[ik(20.0, 4.0)], [ik(30.0, 3.5)]])
    t, r = row.data["spread"]
    assert (t["max"], t["worst_margin"]) == (30.0, 20.0)
    assert (r["min"], r["worst_margin"], r["sense"]) == (3.5, 0.5, "≥")
    assert row.status == PASS
    reported = [Row("G", "rate", f"{v} Hz", "report", REPORT) for v in (124.9, 125.1)]
    (row,) = runs.combine([[reported[0]], [reported[1]]])
    assert row.status == REPORT and row.value == "run 1: 124.9 Hz ‖ run 2: 125.1 Hz"


def test_rows_keep_their_first_order_and_equal_metrics_their_own_places():
    a, b = Row("G", "a", "1", "t", PASS), Row("G", "b", "2", "t", PASS)
    twin = Row("G", "a", "3", "t", FAIL)               # the same metric twice in one run
    combined = runs.combine([[a, b, twin], [a, b, twin]])
    assert [(r.metric, r.status) for r in combined] == [("a", PASS), ("b", PASS), ("a", FAIL)]


def test_the_written_table_shows_spread_margin_and_runs_met(tmp_path):
    rows = runs.combine([[rtt_row(0.61)], [rtt_row(1.503)], [rtt_row(0.72)]])
    json_path, md_path = write(rows, tmp_path, tmp_path, "now", 1.0, [], {}, runs=3)
    md = md_path.read_text()
    assert "| metric | min / median / max | target | margin, worst run | runs met | result |" in md
    assert (f"| {RTT} | p99 0.61 / 0.72 / 1.503 ms | ≤ 1 ms | −0.503 ms | 2 of 3 | FAIL [1] |"
            in md)
    assert "**0 pass, 1 fail" in md and "3 runs" in md
    doc = json.loads(json_path.read_text())
    assert doc["runs"] == 3 and doc["rows"][0]["data"]["spread"][0]["values"] == [0.61, 1.503,
                                                                                  0.72]


def test_one_run_keeps_the_four_column_table(tmp_path):
    _, md_path = write([rtt_row(0.61)], tmp_path, tmp_path, "now", 1.0, [], {})
    assert f"| {RTT} | p99 0.610 ms | ≤ 1 ms | pass |" in md_path.read_text()


# ---- the rows' own bounds agree with their results -----------------------------------------

def _agree(rows):
    judged_rows = [r for r in rows if r.status in (PASS, FAIL)]
    assert judged_rows
    for r in judged_rows:
        assert r.bounds, f"{r.metric}: a judged row without the numbers it is judged on"
        assert (r.status == PASS) == all(b.met for b in r.bounds), r.metric
    return judged_rows


@pytest.mark.parametrize("p99", [0.61, 1.0, 1.503])
def test_the_controller_round_trip_row_is_judged_on_its_bound(p99):
    from bench import floor_targets
    table = [Row("ctl", "servo_j round trip p50 / p99 / max, idle", "…", "report", REPORT,
                 data={"rtt_ms": {"p50": 0.2, "p99": p99, "max": 3.0}})]
    rows = floor_targets.rows(table, "sim", "streams", "ctl")
    (rtt,) = [r for r in rows if r.metric == RTT]
    _agree([rtt])
    assert rtt.bounds == [Bound(p99, 1.0, "ms", True, "p99")]
    assert {r.status for r in rows if r is not rtt} == {NOT_RUN}   # their inputs missing


@pytest.mark.parametrize("p99, rate", [(9.0, 125.1), (10.5, 125.1), (9.0, 124.2)])
def test_state_topic_rows_are_judged_on_their_bounds(p99, rate):
    from bench import state_topics
    stats = {"joint_position": {"rate_hz": rate, "messages": 1000,
                                "interarrival_ms": {"p50": 8.0, "p99": p99, "max": 12.0},
                                "age_ms": {"p50": 0.5, "p99": 7.0, "max": 9.0}}}
    _agree(state_topics.rows("sim", "idle", stats))
    assert all(not r.bounds for r in state_topics.rows("ctl", "idle", stats, judge=False))


def test_node_cpu_rows_are_judged_on_their_bounds():
    from bench import node_resources
    w = {"cpu_percent": 10.5, "rss_mib": 200, "peak_rss_mib": 210, "machine_percent": 50,
         "window_s": 30}
    (row,) = _agree(node_resources.rows("sim", {"idle": w}))
    assert row.status == FAIL and row.bounds[0].margin == pytest.approx(-0.5)


@pytest.mark.parametrize("controller, twin, passes", [(5.8, 3.5, False), (4.6, 3.5, True)])
def test_the_controller_cpu_row_compares_the_two_nodes_measured_over_one_window(controller,
                                                                               twin, passes):
    from bench import floor_targets, node_suite

    def cpu(percent):
        return {"cpu_percent": percent, "window_s": 20.0, "rss_mib": 120, "peak_rss_mib": 120,
                "machine_percent": 12}
    # the apart rows say the opposite of the pair: only the pair may be judged
    table = [Row("sim", "node CPU and RSS, idle", "…", "report", REPORT, data=cpu(9.0)),
             Row("ctl", "node CPU and RSS, idle", "…", "report", REPORT, data=cpu(1.0)),
             node_suite.side_by_side_row("ctl", {"controller": cpu(controller),
                                                 "twin": cpu(twin)})]
    rows = floor_targets.rows(table, "sim", "streams", "ctl")
    (row,) = [r for r in rows if r.metric.startswith("controller backend: node CPU idle")]
    _agree([row])
    assert row.bounds == [Bound(pytest.approx(controller - twin), 2.0, "points", True,
                                "above the twin's")]
    assert (row.status == PASS) == passes


def test_a_slow_half_second_shows_in_its_block_s_p99_and_in_the_range_the_row_reports():
    from bench import servo_latency
    # 5 blocks of 2000 calls at 0.2 ms; the second half second slow for 60 of its calls
    rtt = np.full(5 * servo_latency.RTT_BLOCK, 0.2e-3)
    rtt[2000:2060] = 1.3e-3
    blocks = servo_latency.block_p99s(rtt)
    assert len(blocks) == 5
    assert blocks[1] == pytest.approx(1.3) and blocks[0] == pytest.approx(0.2)
    text = servo_latency._blocks({"rtt_s": rtt, "seconds": 10.0})
    assert "over 10 s" in text and "0.20–1.30 ms" in text
    assert servo_latency._blocks({"rtt_s": rtt[:3000], "seconds": 1.0}) == ""   # one block
