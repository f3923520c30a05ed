#!/usr/bin/env python3
"""The measurement scripts of docs/prognosis.md ("Against the targets": leading indicators, episodes, fleet prior)
on inputs whose answers are known by hand: the jump detector sees no future, the renewal forecast of equal
episodes is exact, the fleet prior's quantiles are those of the library's remaining times."""
import math
import os
import sys
import tempfile
import unittest

BENCH = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "bench")
sys.path.insert(0, BENCH)

import prognosis_episodes as episodes  # noqa: E402
import prognosis_fleet_prior as fleet  # noqa: E402
import prognosis_indicators as indicators  # noqa: E402


def stepped(steps, n=900, size=0.5):
    """A log level with a small deterministic wiggle (so the MAD is not 0) and steps of `size` at `steps`."""
    v = []
    for t in range(n):
        v.append((0.01 if t % 3 == 0 else -0.01 if t % 3 == 1 else 0.0) + size * sum(t >= s for s in steps))
    return v


class JumpDetector(unittest.TestCase):
    def test_a_step_is_found_two_snapshots_after_it_by_the_five_snapshot_median(self):
        self.assertEqual(indicators.jump_onsets(stepped([600, 700])), [602, 702])

    def test_no_step_no_jump(self):
        self.assertEqual(indicators.jump_onsets(stepped([])), [])

    def test_onsets_known_at_t_use_no_data_after_t(self):
        v = stepped([560, 610, 680, 800])
        full = indicators.jump_onsets(v)
        for t in range(500, len(v), 7):
            self.assertEqual(indicators.jump_onsets(v[:t + 1]), [o for o in full if o <= t], t)


class RenewalForecast(unittest.TestCase):
    def test_equal_holds_and_steps_give_the_exact_time(self):
        # Steps of 0.5 every 60 snapshots (10 h): 3 completed episodes on record at t = 700 (onsets 522..702).
        onsets_true = [520, 580, 640, 700]
        v = stepped(onsets_true, n=760)
        onsets = indicators.jump_onsets(v)
        self.assertEqual(onsets, [o + 2 for o in onsets_true])
        t = 730  # 28 snapshots = 4.67 h into the current hold, level 2.0 above the start
        q, why = episodes.forecast(v, t, target=v[t] + 1.2, onsets=onsets, seed=1)
        self.assertEqual(why, "")
        # Each step measured over an episode is 0.5 (the wiggle's medians cancel); 1.2 needs 3 steps:
        # the rest of this hold (10 - 28/6 h), then two more holds of 10 h.
        expected = 10.0 - 28 / 6.0 + 20.0
        for x in q:
            self.assertAlmostEqual(x, expected, places=6)

    def test_hours_come_from_the_times_so_a_recording_gap_counts(self):
        # The same equal episodes, with a 5-h recording gap inside the current hold: 5 h less to wait.
        onsets_true = [520, 580, 640, 700]
        v = stepped(onsets_true, n=760)
        hours = [k / 6.0 + (5.0 if k >= 715 else 0.0) for k in range(len(v))]
        onsets = indicators.jump_onsets(v)
        q, why = episodes.forecast(v, 730, target=v[730] + 1.2, onsets=onsets, seed=1, hours=hours)
        self.assertEqual(why, "")
        self.assertAlmostEqual(q[1], 10.0 - (28 / 6.0 + 5.0) + 20.0, places=6)

    def test_sim_trace_runs_are_read_with_their_times_first_alarm_and_baseline(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "sim.txt")
            with open(path, "w") as f:
                f.write("trace 3 warning actual=1.00 twin=unknown 0 [0, 0]\nrun 7 gaussian 2 0.5\n")
                for k in range(4):
                    f.write("series %d %d %.6f\n" % (k, k * 1800 * 10 ** 9, 0.5 * (1 + k)))
                f.write("run 8 uniform -1 0.5\nseries 0 0 0.5\n")
            runs = episodes.sim_runs(path)
            self.assertEqual(len(runs), 1, "a run without a first alarm is not scored")
            v, hours, first, base = runs[0]
            self.assertEqual(first, 2)
            self.assertAlmostEqual(hours[3], 1.5)
            self.assertAlmostEqual(v[1], math.log(1.0))
            self.assertAlmostEqual(base, math.log(0.5))

    def test_unknown_before_two_completed_episodes(self):
        v = stepped([600, 660], n=700)
        q, why = episodes.forecast(v, 690, target=3.0, onsets=indicators.jump_onsets(v), seed=1)
        self.assertIsNone(q)
        self.assertEqual(why, "fewer than 2 completed episodes")


class FleetPrior(unittest.TestCase):
    def write_trace(self, path, runs, starts=None):
        """runs: per run {level: T hours}; decision points every 10 min from snapshot starts[i] (500) on."""
        with open(path, "w") as f:
            for i, r in enumerate(runs):
                s = starts[i] if starts else 500
                for k in range(int(max(r.values()) * 6)):
                    for level, T in r.items():
                        if k / 6.0 < T:
                            f.write("trace %d %s actual=%.4f twin=unknown 0 [0, 0]\n" % (s + k, level, T - k / 6.0))

    def test_a_run_that_starts_after_the_previous_one_ended_is_still_a_new_run(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "t.txt")
            self.write_trace(path, [{"warning": 2.0, "critical": 3.0}, {"warning": 5.0, "critical": 6.0}],
                             starts=[500, 600])
            runs = fleet.runs(path)
            self.assertEqual([len(r["critical"]) for r in runs], [18, 36])
            self.assertAlmostEqual(runs[1]["warning"][0][1], 5.0, places=3)

    def test_survival_quantiles_and_the_channel_own_pace(self):
        with tempfile.TemporaryDirectory() as d:
            lib_path = os.path.join(d, "lib.txt")
            # 20 runs: warning at T/2, critical at T, end of life at 1.25 T, T = 10 .. 29 h.
            self.write_trace(lib_path, [{"warning": T / 2.0, "critical": float(T), "end_of_life": 1.25 * T}
                                        for T in range(10, 30)])
            runs = fleet.runs(lib_path)
            self.assertEqual(len(runs), 20)
            lib = [{lvl: pts[0][1] for lvl, pts in r.items()} for r in runs]
            self.assertAlmostEqual(lib[3]["critical"], 13.0, places=3)
            # survival at e = 5 h: remaining 5 .. 24 h, 5 % point 5 + 0.05 * 19, median 14.5, 95 % 5 + 0.95 * 19
            q = fleet.forecast(lib, "critical", 5.0, None, paced=False)
            self.assertAlmostEqual(q[0], 5.95, places=3)
            self.assertAlmostEqual(q[1], 14.5, places=3)
            self.assertAlmostEqual(q[2], 23.05, places=3)
            # paced: every library run reaches critical at 2x its warning time; warning after 15 h -> 30 h.
            q = fleet.forecast(lib, "critical", 18.0, 15.0, paced=True)
            for x in q:
                self.assertAlmostEqual(x, 12.0, places=3)
            # outlived the fleet: fewer than 8 runs last longer than 25 h
            self.assertIsNone(fleet.forecast(lib, "critical", 25.0, None, paced=False))


if __name__ == "__main__":
    unittest.main()
