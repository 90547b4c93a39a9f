#!/usr/bin/env python3
"""Tests of conformance_report.py and seed_study.py on synthetic canonical JSON (unittest)."""
import contextlib
import io
import json
import math
import os
import re
import statistics
import sys
import tempfile
import unittest
import xml.etree.ElementTree as ET

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import conformance_report  # noqa: E402
import seed_study  # noqa: E402

SVG = "{http://www.w3.org/2000/svg}"


def entry(problem, depth, quantity, value, se, reference, spread, passed=True, scored=True, unit="tau"):
    return {"problem": problem, "depth": depth, "depth_unit": unit, "quantity": quantity, "value": value, "se": se,
            "reference": reference, "spread": spread, "relative_error": (value - reference) / reference,
            "scored_error": abs(value - reference) / reference, "scored": scored, "pass": passed}


def write_json(path, entries, seconds=12.0):
    with open(path, "w") as f:
        json.dump({"entries": entries, "seconds": seconds}, f)


KIRK_LABEL = "R(0) <mu0=1> & b/a | C"


def report_of(entries):
    """The report of one VOI-octree JSON holding `entries`, as markdown."""
    with tempfile.TemporaryDirectory() as d:
        write_json(os.path.join(d, "conformance_voi.json"), entries, 1.0)
        with contextlib.redirect_stdout(io.StringIO()):
            conformance_report.main([d])
        with open(os.path.join(d, "conformance_report.md")) as f:
            return f.read()


def kdtree_entries():
    return [entry("1a", 1, "Ed", 0.365, 0.000365, 0.366, 0.002),
            entry("1a", 1, "Eou", 0.375, 0.00075, 0.372, 0.005),
            entry("1a", 1, "Lu", 0.0500, 0.0005, 0.0485, 0.015, passed=False),
            entry("1a", 5, "Ed", 0.0433, 0.0002, 0.0433, 0.003),
            entry("1a", 5, "Lu", 0.0, None, 0.00559, 0.052, passed=False),  # a zero estimate, SE null
            entry("kirk", 0.1, KIRK_LABEL, 0.052, 0.001, 0.05, 0.1, unit=""),
            entry("kirk", 0.2, KIRK_LABEL, 0.098, 0.002, 0.1, 0.1, unit=""),
            entry("kirk", 0.2, "z1% (m)", 19.5, 0.2, 19.9, 0.05, scored=False, passed=False, unit=""),
            entry("kirk", "euphotic zone", "Kd/a", 1.9, 0.02, 2.0, 0.05, unit="")]  # a depth that is a label


def voi_entries():  # problem 1a only, and a problem 3 in metres
    return [entry("1a", 1, "Ed", 0.3662, 0.0003662, 0.366, 0.002),
            entry("3", 5, "Ed", 0.229, 0.00229, 0.230, 0.006, unit="m"),
            entry("3", 60, "Ed", 5.0e-5, 2.0e-6, 5.23e-5, 0.071, unit="m")]


class ReportTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = self.tmp.name
        write_json(os.path.join(self.dir, "conformance_voi.json"), voi_entries(), 3.0)
        write_json(os.path.join(self.dir, "conformance_kdtree.json"), kdtree_entries(), 12.0)
        with contextlib.redirect_stdout(io.StringIO()):
            conformance_report.main([self.dir])
        with open(os.path.join(self.dir, "conformance_report.md")) as f:
            self.md = f.read()

    def tearDown(self):
        self.tmp.cleanup()

    def row(self, *cells):
        """The table row that starts with these cells."""
        start = "| " + " | ".join(cells) + " |"
        rows = [line for line in self.md.splitlines() if line.startswith(start)]
        self.assertEqual(len(rows), 1, start)
        return [c.strip() for c in re.split(r"(?<!\\)\|", rows[0].strip("|"))]

    def test_stores_in_their_usual_order_with_their_names(self):
        self.assertIn("| store | seconds | 1a | kirk | 3 | scored entries passing |", self.md)
        self.assertLess(self.md.index("| k-d tree | 12 |"), self.md.index("| VOI octree | 3 |"))

    def test_table_numbers(self):
        # depth, qty, M93 mean, s/x, k-d tree (SE), err, VOI octree (SE), err, pass, DIRSIG, DIRSIG err
        self.assertEqual(self.row("tau 1", "Ed"), ["tau 1", "Ed", "3.66e-1", "0.2%", "3.650e-1 (0.10%)", "-0.27%",
                                                   "3.662e-1 (0.10%)", "+0.05%", "pass/pass", "3.66e-1", "+0.0%"])
        self.assertEqual(self.row("tau 1", "Lu")[2:], ["4.85e-2", "1.5%", "5.000e-2 (1.00%)", "+3.09%", "-", "-",
                                                       "FAIL/-", "4.88e-2", "+0.6%"])
        # A zero estimate: no relative SE; a depth without a DIRSIG value.
        self.assertEqual(self.row("tau 5", "Lu")[4:6], ["0 (-)", "-100.00%"])
        self.assertEqual(self.row("tau 5", "Ed")[-2:], ["4.34e-2", "+0.2%"])
        # Problem 3 in metres, from the VOI file only.
        self.assertEqual(self.row("60 m", "Ed"), ["60 m", "Ed", "5.23e-5", "7.1%", "5.000e-5 (4.00%)", "-4.40%", "pass",
                                                  "3.46e-5", "-33.8%"])

    def test_kirk_and_reported_rows_shown_as_such(self):
        self.assertIn("| depth | qty | Kirk's relation | s/x | k-d tree (SE) | err | pass | DIRSIG | DIRSIG err |", self.md)
        self.assertEqual(self.row("0.1", "R(0) &lt;mu0=1&gt; &amp; b/a \\| C")[2:7], ["5.00e-2", "10.0%", "5.200e-2 (1.92%)",
                                                                                "+4.00%", "pass"])
        self.assertEqual(self.row("0.2", "z1% (m)")[6], "reported")
        self.assertEqual(self.row("euphotic zone", "Kd/a")[4:7], ["1.900e0 (1.05%)", "-5.00%", "pass"])
        self.assertIn("## Kirk's relations\n", self.md)

    def test_blocked_entries_shown_with_their_reason(self):
        blocked = entry("5", 10, "Ed", 0.01463, 0.00001, 0.0148, 0.007, passed=False, scored=False)
        blocked["blocked"] = "the specification leaves it open"
        md = report_of([blocked])
        self.assertIn("| tau 10 | Ed | 1.48e-2 | 0.7% | 1.463e-2 (0.07%) | -1.15% | blocked |", md)
        self.assertIn("## Blocked entries", md)
        self.assertIn("- problem 5, depth 10, Ed: the specification leaves it open", md)

    def test_a_run_under_another_source_is_a_problem_of_its_own(self):
        scored = entry("4", 1, "Ed", 0.336, 0.0002, 0.323, 0.076)
        reported = entry("4", 1, "Ed", 0.335, 0.0001, 0.323, 0.076, scored=False)
        reported["source"] = "gc-sky"
        md = report_of([scored, reported])
        self.assertIn("| tau 1 | Ed | 3.23e-1 | 7.6% | 3.360e-1 (0.06%) | +4.02% | pass |", md)
        self.assertIn("under gc-sky (reported beside the scored run)", md)
        self.assertIn("| tau 1 | Ed | 3.23e-1 | 7.6% | 3.350e-1 (0.03%) | +3.72% | reported |", md)

    def test_summary_lines(self):
        self.assertIn("- k-d tree (`conformance_kdtree.json`): 3 of 5 scored M93 entries pass; "
                      "3 of 3 scored Kirk entries pass, 1 reported only; failing: 1a tau 1 Lu, 1a tau 5 Lu.", self.md)
        self.assertIn("- VOI octree (`conformance_voi.json`): 3 of 3 scored M93 entries pass.", self.md)
        self.assertIn("| k-d tree | 12 | 3/5 | 3/3 (+1 rep.) | - | 6 of 8 |", self.md)

    def test_one_well_formed_svg_per_problem(self):
        # Markers: one per store and entry in each of a quantity's two panels (the zero
        # estimate of 1a Lu at tau 5 too, on the bottom of the log panel), one per store in
        # the legend.
        for problem, quantities, circles in (("1a", 3, 2 * 6 + 2), ("kirk", 3, 2 * 4 + 1 + 1), ("3", 1, 2 * 2 + 1)):
            self.assertIn(f"![problem {problem}](conformance_{problem}.svg)", self.md)
            root = ET.parse(os.path.join(self.dir, f"conformance_{problem}.svg")).getroot()
            self.assertEqual(root.tag, SVG + "svg")
            texts = [t.text for t in root.iter(SVG + "text")]
            self.assertEqual(sum(1 for t in texts if t and t.endswith(", relative error")), quantities, problem)
            self.assertEqual(len(list(root.iter(SVG + "circle"))), circles, problem)
        # Lu of 1a stays on a log scale despite its zero estimate.
        root = ET.parse(os.path.join(self.dir, "conformance_1a.svg")).getroot()
        self.assertIn("1e-2", [t.text for t in root.iter(SVG + "text")])

    def test_special_characters_and_labels_in_svg(self):
        root = ET.parse(os.path.join(self.dir, "conformance_kirk.svg")).getroot()
        texts = [t.text for t in root.iter(SVG + "text")]
        self.assertIn("kirk: " + KIRK_LABEL, texts)
        self.assertIn("euphotic zone", texts)  # the depth axis of Kd/a, by label


def seed_run(seed, values, ses, passes, reference=1.0, scored=True):
    """A canonical JSON of one seed with one entry per value."""
    return {"entries": [entry("2a", float(i + 1), f"q{i}", values[i][seed], ses[i], reference, 0.05,
                              passed=passes[i][seed], scored=scored) for i in range(len(values))], "seconds": 1.0}


class SeedStudyTest(unittest.TestCase):
    K = 8
    # Entry 0: scatter of values about 1 % with SE 1 % (honest); entry 1: scatter about 5 %
    # with SE 1 % (flagged); entry 2: honest but failing in 2 of 8 seeds (flagged).
    VALUES = [[1.0 + 0.01 * d for d in (-1.2, 0.4, 1.1, -0.3, 0.9, -1.0, 0.2, -0.1)],
              [1.0 + 0.05 * d for d in (-1.2, 0.4, 1.1, -0.3, 0.9, -1.0, 0.2, -0.1)],
              [1.0 + 0.01 * d for d in (-1.2, 0.4, 1.1, -0.3, 0.9, -1.0, 0.2, -0.1)]]
    SES = [0.01, 0.01, 0.01]
    PASSES = [[True] * 8, [True] * 8, [True, False, True, True, False, True, True, True]]

    def runs(self):
        return [(k + 1, seed_run(k, self.VALUES, self.SES, self.PASSES)) for k in range(self.K)]

    def test_aggregation(self):
        rows = seed_study.aggregate(self.runs())
        self.assertEqual(len(rows), 3)
        for row, values in zip(rows, self.VALUES):
            mean = statistics.fmean(values)
            self.assertAlmostEqual(row["mean_error"], mean - 1.0)
            self.assertAlmostEqual(row["scatter"], statistics.stdev(values) / mean)
            self.assertAlmostEqual(row["mean_se"], statistics.fmean(0.01 / v for v in values))
            self.assertAlmostEqual(row["ratio"], row["scatter"] / row["mean_se"])
            self.assertEqual(row["seeds"], 8)
        self.assertEqual([r["passes"] for r in rows], [8, 8, 6])
        self.assertEqual([r["flagged"] for r in rows], [False, True, True])
        self.assertEqual(rows[1]["flags"], ["scatter > 1.5 SE"])
        self.assertEqual(rows[2]["flags"], ["passes < 7"])

    def test_reported_entries_are_not_flagged_for_passes(self):
        runs = [(k + 1, seed_run(k, self.VALUES[2:], self.SES[2:], self.PASSES[2:], scored=False)) for k in range(self.K)]
        (row,) = seed_study.aggregate(runs)
        self.assertIsNone(row["passes"])
        self.assertFalse(row["flagged"])

    def test_from_directory_and_into_the_report(self):
        with tempfile.TemporaryDirectory() as d:
            for seed, data in self.runs():
                with open(os.path.join(d, f"canonical_voi_seed{seed}.json"), "w") as f:
                    json.dump(data, f)
            with contextlib.redirect_stdout(io.StringIO()):
                status = seed_study.main(["--from", d, "--out", d])
            self.assertEqual(status, 1)  # two entries flagged
            with open(os.path.join(d, "seed_study_voi.md")) as f:
                md = f.read()
            self.assertIn("1 of 3 scored entries unflagged; 1 with scatter above 1.5 mean SE", md)
            row = next(line for line in md.splitlines() if line.startswith("| 2a | tau 2 | q1 |"))
            study = seed_study.load_study(os.path.join(d, "seed_study_voi.json"))
            r = study["entries"][1]
            self.assertIn(f"| {100 * r['scatter']:.2f}% | {100 * r['mean_se']:.2f}% | {r['ratio']:.2f} | 8/8 | "
                          "**scatter > 1.5 SE** |", row)
            self.assertEqual(study["seeds"], list(range(1, 9)))
            # The report of a directory adds the seed study found there.
            write_json(os.path.join(d, "conformance_voi.json"), voi_entries())
            with contextlib.redirect_stdout(io.StringIO()):
                conformance_report.main([d])
            with open(os.path.join(d, "conformance_report.md")) as f:
                report = f.read()
            self.assertIn("## Seed study: VOI octree", report)
            self.assertIn(row, report)

    def test_tally_and_the_chance_of_a_flag(self):
        t = seed_study.tally(seed_study.aggregate(self.runs()))
        self.assertEqual((t["scored"], t["flagged"], t["over_ratio"], t["few_passes"]), (3, 2, 1, 1))
        rows = seed_study.aggregate(self.runs())
        self.assertAlmostEqual(t["rms_ratio"], math.sqrt(sum(r["ratio"] ** 2 for r in rows) / 3))
        # The 95 % quantiles of chi-square with 1, 2, 3 and 5 degrees of freedom.
        for x, dof in ((3.841458820694124, 1), (5.991464547107979, 2), (7.814727903251179, 3), (11.070497693516351, 5)):
            self.assertAlmostEqual(seed_study.chi2_survival(x, dof), 0.05, places=12)
        # Over 8 seeds an honest SE shows a scatter above 1.5 SE in 2.75 % of the entries.
        self.assertAlmostEqual(seed_study.chance_over_limit(8), 0.0275, places=4)
        self.assertAlmostEqual(t["expected_over_ratio"], 3 * seed_study.chance_over_limit(8))

    def test_a_single_seed_has_no_scatter(self):
        (row, *_) = seed_study.aggregate(self.runs()[:1])
        self.assertTrue(math.isnan(row["scatter"]) and math.isnan(row["ratio"]))


if __name__ == "__main__":
    unittest.main()
