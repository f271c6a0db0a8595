"""The C export: the reference evaluator compiled with gcc gives the Python evaluator's numbers."""

import re
import shutil
import subprocess

import numpy as np
import pytest

from corneasim.surrogate import build_surrogate, synthetic, write_c_export
from corneasim.surrogate.c_export import EVALUATOR

MAIN = """#include <stdio.h>
#include "surrogate_model.h"
int main(void) {
    const double x[][2] = {{1.5, 0.17}, {4.4, 0.24}, {3.0, 0.2}};
    const double depth[] = {0.0, 0.05, 0.21, 0.33, 0.5, 0.79, 0.95, 1.0};
    for (int c = 0; c < 3; c++) for (int k = 0; k < 8; k++) {
        double mean, half;
        surrogate_force(&SURROGATE, x[c], depth[k], &mean, &half);
        printf("%.17g %.17g\\n", mean, half);
    }
    return 0;
}
"""


def test_evaluator_is_at_most_30_lines():
    body = EVALUATOR[EVALUATOR.index("static void surrogate_force"):]
    assert len(body.strip().splitlines()) <= 30


@pytest.mark.skipif(shutil.which("gcc") is None, reason="needs gcc")
def test_compiled_evaluator_matches_python(tmp_path):
    study = synthetic.write_study(tmp_path / "study", count=8, samples=200)
    model = build_surrogate(study, hold_out=0.0)
    write_c_export(model, tmp_path)
    (tmp_path / "main.c").write_text(MAIN)
    subprocess.run(["gcc", "-std=c99", "-O2", "-Wall", "-Werror", "-o", str(tmp_path / "main"),
                    str(tmp_path / "main.c"), "-lm"], check=True, cwd=tmp_path)
    printed = subprocess.run([str(tmp_path / "main")], capture_output=True, text=True, check=True).stdout
    out = np.array([[float(v) for v in line.split()] for line in printed.splitlines()])
    expected = []
    for rate, diameter in ((1.5, 0.17), (4.4, 0.24), (3.0, 0.2)):
        mean, lower, upper = model.force([0.0, 0.05, 0.21, 0.33, 0.5, 0.79, 0.95, 1.0], extrapolate=True,
                                         rate=rate, diameter=diameter)
        expected += list(zip(mean, upper - mean))
    expected = np.array(expected)
    np.testing.assert_allclose(out[:, 0], expected[:, 0], rtol=1e-10, atol=1e-12)
    # the variance is a difference of near-equal sums: round-off differs in the last digits
    np.testing.assert_allclose(out[:, 1], expected[:, 1], rtol=1e-7)


def test_header_documents_the_inputs(tmp_path):
    study = synthetic.write_study(tmp_path / "study", count=6, samples=100)
    _, header = write_c_export(build_surrogate(study, hold_out=0.0), tmp_path)
    text = header.read_text()
    assert re.search(r"x\[0\] instrument\.motion\.insertion\.rate \(mm/s\) in \[", text)
    assert re.search(r"x\[1\] instrument\.shape\.diameter \(mm\) in \[", text)
