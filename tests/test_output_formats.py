"""Outputs that standard tools open: fields.xmf through meshio's XDMF time-series reader (the
reader ParaView's XDMF3 format shares), interface.csv and columns.csv through pandas at every
record time, and the DataFrames of the Python API (units in the column names)."""

import h5py
import meshio
import numpy as np
import pandas as pd
import pytest

from cone_shot import cone_deck
from shockfriction.hydro.api import run_dict


@pytest.fixture(scope="module")
def cone_run(tmp_path_factory):
    """The coarse cone shot (1.3k zones) with sub-grid thermoelastic friction, 3 us, fields every us."""
    out = tmp_path_factory.mktemp("cone")
    deck = cone_deck(law="subgrid-thermoelastic", cell_um=400, end_us=3.0, cells=40, record_ns=500,
                     profile_nodes=[0, 30, 60], profile_interval="1 us", field_interval_us=1.0)
    return run_dict(deck, out), out


def test_meshio_reads_every_field_output(cone_run):
    res, out = cone_run
    with h5py.File(out / "fields.h5") as f:
        steps = sorted(k for k in f if k.startswith("step_"))
        times = [f[k].attrs["time"] for k in steps]
        final_y = f[steps[-1]]["y"][()]
    assert len(steps) == 4  # t = 0, 1, 2, 3 us
    with meshio.xdmf.TimeSeriesReader(out / "fields.xmf") as reader:
        points, cells = reader.read_points_cells()
        assert reader.num_steps == len(steps)
        assert points.shape == (res.mesh.n_nodes, 2)
        assert cells[0].type == "quad" and cells[0].data.shape == (res.mesh.n_cells, 4)
        np.testing.assert_array_equal(cells[0].data, res.mesh.conn)
        for k in range(reader.num_steps):
            t, point_data, cell_data = reader.read_data(k)
            assert t == pytest.approx(times[k], rel=1e-12)
            assert set(point_data) == {"vx", "vy", "x", "y"}
            assert {"rho", "p", "T", "sxx", "szz", "body"} <= set(cell_data)
            assert cell_data["rho"][0].shape == (res.mesh.n_cells,)
            assert np.all(cell_data["rho"][0] > 0.0)
        np.testing.assert_array_equal(point_data["y"], final_y)  # the moving mesh, last output
    np.testing.assert_array_equal(point_data["y"], res.state.y)


def test_interface_and_column_csv_open_at_every_record_time(cone_run):
    _, out = cone_run
    iface = pd.read_csv(out / "interface.csv")
    assert {"line", "t [s]", "node", "x [m]", "sigma_n [Pa]", "tau [Pa]", "slip [m/s]",
            "theta_interface [K]"} <= set(iface.columns)
    with h5py.File(out / "interface.h5") as f:
        for name in ("cone_wall", "barrel"):
            rows = iface[iface["line"] == name]
            t = f[name]["t_s"][()]
            nn = f[name]["node_index"].size
            assert t.size >= 6
            # every record (time-major, nodes along the slave side); a last partial window may
            # close a few ns after the previous record, so times are matched row by row
            assert len(rows) == t.size * nn
            np.testing.assert_allclose(rows["t [s]"], np.repeat(t, nn), rtol=1e-9)
            np.testing.assert_array_equal(rows["node"], np.tile(np.arange(nn), t.size))
            np.testing.assert_allclose(rows["sigma_n [Pa]"], f[name]["sigma_n_Pa"][()].reshape(-1),
                                       rtol=1e-9, atol=1e-300)
    cols = pd.read_csv(out / "columns.csv")
    with h5py.File(out / "columns.h5") as f:
        g = f["cone_wall"]
        t, nz = g["t_s"][()], g["z_m"].size
        assert t.size >= 3
        np.testing.assert_allclose(np.unique(cols["t [s]"]), t, rtol=1e-9)
        assert (cols.groupby("t [s]").size() == 3 * nz).all()
        theta = cols.sort_values(["t [s]", "node", "z [m]"], kind="stable")["theta [K]"].to_numpy()
        np.testing.assert_allclose(theta, g["theta_K"][()].reshape(-1), rtol=1e-9)
    assert cols["theta [K]"].max() > 300.0  # friction heated the layer


def test_api_dataframes_carry_units(cone_run):
    res, out = cone_run
    probes = res.probes_df
    assert list(probes.columns) == ["t [s]", "cone_fs.vy [m/s]", "confinement_fs.vy [m/s]"]
    np.testing.assert_array_equal(probes["cone_fs.vy [m/s]"], res.probes["cone_fs.vy"])
    energy = res.energy_df
    assert {"t [s]", "kinetic [J]", "total [J]", "error [J]"} <= set(energy.columns)
    np.testing.assert_array_equal(energy["total [J]"], res.energy["total"])
    csv = pd.read_csv(out / "probes.csv")
    assert len(csv) == len(probes)
    assert res.interface_df.shape == pd.read_csv(out / "interface.csv").shape
    assert len(res.columns_df) == len(pd.read_csv(out / "columns.csv"))


def test_dataframes_without_an_output_folder(cone_run):
    deck = cone_deck(law="coulomb", cell_um=400, end_us=0.5, record_ns=100)
    res = run_dict(deck)
    frame = res.interface_df
    assert set(frame["line"]) == {"cone_wall", "barrel"}
    assert {"t [s]", "sigma_n [Pa]", "slip [m/s]"} <= set(frame.columns)
    assert res.columns_df.empty
    assert res.energy_df["t [s]"].iloc[-1] == pytest.approx(0.5e-6)
