"""``report.html``: one valid, self-contained page of a results folder with the summary's figures;
``corneasim report`` on a bad folder is one line and exit 2; the targets' verdicts."""

import base64
import io
import json
from html.parser import HTMLParser

import matplotlib.image
import numpy as np
import pytest
from matplotlib.figure import Figure

from corneasim.cli.main import main
from corneasim.output import REPORT, Image, Mark, Paragraph, Section, Table, render_page, score, write_run_report

VOID = {"meta", "img", "br", "hr", "link", "input"}


class Page(HTMLParser):
    """Checks that every element is closed in order; collects images and text."""

    def __init__(self):
        super().__init__()
        self.stack, self.errors, self.images, self.links, self.text = [], [], [], [], []

    def handle_starttag(self, tag, attrs):
        attributes = dict(attrs)
        if tag == "img":
            self.images.append(attributes["src"])
        self.links += [attributes[k] for k in ("href",) if k in attributes]
        if tag not in VOID:
            self.stack.append(tag)

    def handle_endtag(self, tag):
        if not self.stack or self.stack.pop() != tag:
            self.errors.append(tag)

    def handle_data(self, data):
        self.text.append(data)


def parse(text):
    page = Page()
    page.feed(text)
    page.close()
    return page


def _png(path, colour):
    figure = Figure(figsize=(2, 1.5))
    figure.subplots().plot([0, 1], [0, 1], color=colour)
    figure.savefig(path, format="png")


SUMMARY = {
    "scenario": "needle", "kind": "needle", "status": "completed", "peak_force_N": 0.6971,
    "punctures": [{"event": "epithelium", "time_s": 0.209, "depth_mm": 0.2093, "force_N": 0.1234},
                  {"event": "stroma", "time_s": 0.283, "depth_mm": 0.2831, "force_N": 0.2468}],
    "validation": {"dataset": "needle-insertion-force", "column": "experiment_1mm_s_N", "rmse_N": 0.0286,
                   "max_abs_error_N": 0.0612, "rmse_raw_N": 0.0444, "n_points": 15},
    "run": {"elements": 985, "nodes": 1120, "steps": 41000, "wall_s": 12.5, "element_steps_per_s": 3.2e6,
            "max_kinetic_to_internal": 0.071, "energy_balance_error": 3.4e-4, "warnings": ["a warning"],
            "platform": {"processor": "Test CPU 9000", "numba_threads": 1, "python": "3.11.7"}},
}


@pytest.fixture
def folder(tmp_path):
    (tmp_path / "summary.json").write_text(json.dumps(SUMMARY))
    (tmp_path / "scenario.toml").write_text(
        'kind = "needle"\nname = "needle"\n[instrument.motion.insertion]\ntype = "linear"\nrate = 1.0\n'
        '[materials.stroma]\nmaterial = "cornea-needle"\nfailure_limit = 110.0\n'
        '[solver]\nend_time = 0.7\n')
    time = np.linspace(0.0, 0.7, 50)
    columns = {"time_s": time, "kinetic_energy_mJ": 1e-3 * time, "internal_energy_mJ": 0.1 + time,
               "hourglass_energy_mJ": 1e-4 * time, "energy_balance_error": 1e-4 * time}
    (tmp_path / "history.csv").write_text(",".join(columns) + "\n" + "\n".join(
        ",".join(repr(float(columns[c][i])) for c in columns) for i in range(time.size)) + "\n")
    (tmp_path / "plots").mkdir()
    for name, colour in (("force", "C0"), ("stress-end", "C1"), ("stress-stroma", "C2"), ("stress-0.0s", "C3")):
        _png(tmp_path / "plots" / f"{name}.png", colour)
    return tmp_path


def test_report_is_valid_self_contained_html_with_the_summary_figures(folder):
    path = write_run_report(folder)
    assert path == folder / REPORT
    text = path.read_text()
    assert text.startswith("<!DOCTYPE html>")
    page = parse(text)
    assert page.errors == [] and page.stack == []
    # force plot, energies (drawn from the history), three stress maps
    assert len(page.images) == 5 and page.links == []
    for source in page.images:
        prefix = "data:image/png;base64,"
        assert source.startswith(prefix)
        pixels = matplotlib.image.imread(io.BytesIO(base64.b64decode(source[len(prefix):], validate=True)))
        assert pixels.ndim == 3 and pixels.shape[0] > 10
    assert (folder / "plots" / "energies.png").is_file()
    words = " ".join(page.text)
    for figure in ("<= 0.035 N", "0.0286", "0.2093", "0.2831", "12.5 s", "41000", "Test CPU 9000", "cornea-needle", "1 mm/s",
                   "a warning"):
        assert figure in words, figure
    # the maps in time order: the instant 0 s, the stroma puncture (0.283 s), the end
    maps = words.index("Stress maps")
    assert maps < words.index("t = 0.0 s") < words.index("stroma punctured") < words.index("end of the run")


def test_verdicts_follow_the_targets():
    rows = {quantity: (value, met) for quantity, value, _, met in score(SUMMARY, 1.0)}
    assert rows["RMSE of the fitted force vs experiment_1mm_s_N, N"] == (0.0286, True)
    assert rows["largest kinetic / internal energy after contact"] == (0.071, False)
    assert score(dict(SUMMARY, validation=dict(SUMMARY["validation"], rmse_N=0.05)), 1.0)[0][3] is False
    assert score(dict(SUMMARY, validation=dict(SUMMARY["validation"], rmse_N=0.09)), 5.0)[0][3] is True
    trephine = {"kind": "trephine", "peak_fz_N": 0.13, "validation": {
        "fz": {"rmse_N": 0.021}, "fc": {"rmse_N": 0.004}, "peak_fz_experiment_table_N": 0.1492}}
    verdicts = {quantity: met for quantity, _, _, met in score(trephine)}
    # 0.13 is 12.9% under 0.1492 N: within 15%
    assert verdicts["F_z RMSE vs the experiment, N"] is False
    assert verdicts["F_c envelope RMSE vs the experiment, N"] is True
    assert verdicts["peak F_z, N"] is True


def test_page_generator_escapes_text_and_embeds_images(tmp_path):
    _png(tmp_path / "a.png", "k")
    text = render_page("A <study>", [
        Section("One & two", [Paragraph("x < y"), Table(["a", "b"], [[1.5, Mark("met", True)], [None, "<td>"]]),
                              Image.from_file(tmp_path / "a.png", "caption")])], subtitle="sub")
    page = parse(text)
    assert page.errors == [] and len(page.images) == 1
    assert "A <study>" in page.text and "x < y" in page.text and "<td>" in page.text
    assert 'class="met"' in text and "&lt;study&gt;" in text


def _cli(capsys, *arguments):
    with pytest.raises(SystemExit) as exit_status:
        main(list(arguments))
    return exit_status.value.code, capsys.readouterr()


def test_bad_results_folder_is_one_line_and_exit_2(tmp_path, capsys):
    for folder in (tmp_path / "missing", tmp_path):
        code, output = _cli(capsys, "report", str(folder))
        assert code == 2
        assert len(output.err.strip().splitlines()) == 1 and "results folder" in output.err


def test_report_command_writes_the_page_and_has_a_purpose_and_an_example(folder, capsys):
    code, output = _cli(capsys, "report", str(folder))
    assert code == 0 and (folder / REPORT).is_file() and str(folder / REPORT) in output.out
    code, output = _cli(capsys, "report", "--help")
    assert code == 0
    assert "report.html" in output.out and "example: corneasim report results/needle" in output.out
