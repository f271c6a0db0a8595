"""The papers' datasets: shapes, units, spot values from the papers, internal consistency."""

import numpy as np
import pytest

from corneasim.analysis import gaussian_sum
from corneasim.data import list_datasets, load_dataset, load_dataset_file
from corneasim.errors import InputError

EXPECTED = {
    "needle-insertion-force": (15, 5),
    "needle-insertion-gaussian-fit": (3, 4),
    "trephination-force": (13, 6),
    "trephination-gaussian-fit": (2, 4),
    "porcine-eye-geometry": (1, 9),
}


def test_registry_lists_every_dataset():
    assert list_datasets() == sorted(EXPECTED)


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_every_dataset_loads_with_shape_units_and_source(name):
    dataset = load_dataset(name)
    n_rows, n_columns = EXPECTED[name]
    assert dataset.n_rows == n_rows and len(dataset.columns) == n_columns
    assert all(column.shape == (n_rows,) for column in dataset.columns.values())
    assert dataset.title and dataset.source and dataset.notes
    assert ("needle" in dataset.source) or ("trephin" in dataset.source)
    assert all(unit in ("", "mm", "um", "s", "N") for unit in dataset.units.values())
    assert sum(unit == "" for unit in dataset.units.values()) <= 1  # only 'term'


def test_needle_table2_spot_values():
    table = load_dataset("needle-insertion-force")
    np.testing.assert_allclose(table["depth_mm"], np.linspace(0.0, 0.7, 15), atol=1e-12)
    assert table.units["experiment_5mm_s_N"] == "N"
    row = {name: values[10] for name, values in table.columns.items()}  # depth 0.5 mm
    assert row == {"depth_mm": 0.5, "experiment_1mm_s_N": 0.36, "simulation_1mm_s_N": 0.38,
                   "experiment_5mm_s_N": 0.55, "simulation_5mm_s_N": 0.57}
    assert table["experiment_5mm_s_N"][9] == 0.15  # the dip at 0.45 mm
    assert table["simulation_5mm_s_N"][0] == 0.02
    assert any("mm/s" in note for note in table.notes)


def test_eq16_reproduces_the_1mm_s_simulation_column():
    table = load_dataset("needle-insertion-force")
    fit = load_dataset("needle-insertion-gaussian-fit")
    assert list(fit["term"]) == [1, 2, 3]
    assert list(fit["a_N"]) == [0.46, 0.40, 0.22] and list(fit["b_mm"]) == [0.61, 0.86, 0.36]
    predicted = gaussian_sum(table["depth_mm"], fit["a_N"], fit["b_mm"], fit["c_mm"])
    error = np.abs(predicted - table["simulation_1mm_s_N"])
    assert error.max() < 0.017  # the note's 0.016 N, at 0.50 mm
    assert int(np.argmax(error)) == 10


def test_trephination_table_is_converted_to_newtons():
    table = load_dataset("trephination-force")
    # text: peak simulated Fz at point C is 14.40e-2 N (62.5 s); max simulated Fc about 3.55e-2 N
    assert table["simulation_Fz_N"].max() == pytest.approx(0.1440)
    assert table["time_s"][np.argmax(table["simulation_Fz_N"])] == 62.5
    assert table["simulation_Fc_N"].max() == pytest.approx(0.0355)
    assert table["experiment_Fc_N"].max() == pytest.approx(0.0240)  # text: "less than 2.40e-2 N"
    # displacement = 20 um/s x time (loading of the paper)
    np.testing.assert_allclose(table["displacement_um"], 20.0 * table["time_s"], rtol=1e-12)


def test_eq14_matches_the_table_only_where_the_docs_say():
    table = load_dataset("trephination-force")
    fit = load_dataset("trephination-gaussian-fit")
    time, fz = table["time_s"], table["simulation_Fz_N"]
    predicted = gaussian_sum(time, fit["a_N"], fit["b_s"], fit["c_s"])
    inside = (time >= 3.5) & (time <= 65) & (time != 62.5)
    assert np.max(np.abs(predicted - fz)[inside]) < 0.006
    assert predicted[time == 62.5][0] == pytest.approx(0.1056, abs=1e-4)  # table holds 0.1440
    assert np.all(predicted[time > 70] < 0.021) and np.all(fz[time > 70] > 0.095)


def test_geometry_table1():
    geometry = load_dataset("porcine-eye-geometry")
    assert geometry["central_thickness_mm"][0] == 0.55
    assert geometry["anterior_radius_mm"][0] == 7.80 and geometry["posterior_radius_mm"][0] == 6.80
    assert geometry["axial_length_mm"][0] == 26.50


def test_unknown_name_and_column():
    with pytest.raises(InputError, match="unknown dataset 'nope'.*needle-insertion-force"):
        load_dataset("nope")
    with pytest.raises(InputError, match="unknown column 'force'"):
        load_dataset("porcine-eye-geometry")["force"]


def test_user_file_with_metadata(tmp_path):
    path = tmp_path / "mine.csv"
    path.write_text("# title: my test\n#   continued\n# source: bench\nx_mm,f_N\n0,1\n")
    dataset = load_dataset_file(path)
    assert dataset.name == "mine" and dataset.title == "my test continued" and dataset.source == "bench"
    assert dataset.units == {"x_mm": "mm", "f_N": "N"} and dataset.notes == ()
