"""``corneasim surrogate build | check | predict`` as a user runs them: output, exit codes, one-line errors
(through the CLI's parser and error path in this process; a folder that is not a study through the entry point)."""

from cli_helpers import corneasim, corneasim_here

from corneasim.surrogate import synthetic


def test_build_check_and_out_of_range(tmp_path):
    study = synthetic.write_study(tmp_path / "study", count=8, samples=150)
    model = tmp_path / "model.npz"
    built = corneasim_here("surrogate", "build", str(study), "--out", str(model), "--hold-out", "0.25")
    assert built.returncode == 0, built.stderr
    checked = corneasim_here("surrogate", "check", str(model))
    assert checked.returncode == 0, checked.stderr
    assert "instrument.motion.insertion.rate (rate): " in checked.stdout and " mm/s" in checked.stdout
    assert "trained on 6 cases" in checked.stdout and "2 held out" in checked.stdout
    assert "held-out (2 cases): force_N RMSE/peak" in checked.stdout
    refused = corneasim_here("surrogate", "predict", str(model), "rate=9", "diameter=0.2", "--at", "0.3")
    assert refused.returncode == 2
    assert refused.stderr.count("\n") == 1 and "rate = 9 mm/s is outside the training range" in refused.stderr
    allowed = corneasim_here("surrogate", "predict", str(model), "rate=9", "diameter=0.2", "--at", "0.3", "--extrapolate")
    assert allowed.returncode == 0 and "depth_mm 0.3: " in allowed.stdout


def test_not_a_study_is_one_line(tmp_path):
    result = corneasim("surrogate", "build", str(tmp_path), "--out", str(tmp_path / "m.npz"))
    assert result.returncode == 2
    assert result.stderr.strip().endswith("no study.toml (not a study folder)")
    assert result.stderr.count("\n") == 1
