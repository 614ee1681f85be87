"""End-of-run products (maps, column profiles, CSV tables) made by worker processes on a run with threads:
the same bytes as made one after another in the run's process, and a failed worker redone there."""

import logging
import shutil
import sys

import pytest

from shockfriction.hydro.api import prepare, run_simulation
from shockfriction.io import products

FILES = ["interface_interface.png", "interface.csv", "subgrid_interface.png", "columns_interface.png",
         "columns.csv"]


@pytest.fixture(scope="module")
def two_thread_run(coupled_decks, tmp_path_factory):
    """A coupled strip run on two threads, its products made by workers (spied on)."""
    out = tmp_path_factory.mktemp("products") / "out"
    calls = []
    real = products._in_worker
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(products, "_in_worker", lambda o, share: calls.append(share) or real(o, share))
        sim = prepare(coupled_decks["strip"](model="thermoelastoplastic", end="0.4 us", record="10 ns"), threads=2)
        assert sim.parallel
        run_simulation(sim, out)
    return out, calls


def _records_only(src, dst):
    dst.mkdir()
    for name in ("interface.h5", "columns.h5"):
        shutil.copy(src / name, dst / name)


def test_shares_go_to_the_least_loaded_worker_longest_first():
    every = list(products.PRODUCTS)
    assert products.shares(every, 2) == [["interface_maps", "columns_table"],
                                         ["interface_table", "subgrid_maps", "column_profiles"]]
    assert products.shares(every, 3) == [["interface_maps"], ["interface_table", "columns_table"],
                                         ["subgrid_maps", "column_profiles"]]
    assert products.shares(every[:2], 8) == [["interface_maps"], ["interface_table"]]


def test_workers_make_every_product_and_the_same_bytes_as_one_process(two_thread_run, tmp_path):
    out, calls = two_thread_run
    assert calls == products.shares(list(products.PRODUCTS), 2)  # two workers, all five products
    serial = tmp_path / "serial"
    _records_only(out, serial)
    written = products.make_products(serial, workers=1)
    assert [p.name for p in written] == FILES
    for name in FILES:
        assert (out / name).read_bytes() == (serial / name).read_bytes(), name


def test_a_failed_worker_is_redone_in_the_run_process(two_thread_run, tmp_path, monkeypatch, caplog):
    out, _ = two_thread_run
    target = tmp_path / "redo"
    _records_only(out, target)
    real = products.worker_command
    monkeypatch.setattr(products, "worker_command",
                        lambda o, share: [sys.executable, "-c", "raise SystemExit('worker killed')"]
                        if "interface_table" in share else real(o, share))
    with caplog.at_level(logging.WARNING, logger="shockfriction.io.products"):
        written = products.make_products(target, workers=3)
    assert [p.name for p in written] == FILES
    assert ("products interface_table, columns_table: their worker process failed (worker killed); making them here"
            in caplog.text)
    assert caplog.text.count("worker process failed") == 1
    assert (target / "interface.csv").read_bytes() == (out / "interface.csv").read_bytes()


def test_a_worker_with_a_wrong_product_exits_2():
    assert products.main(["out", "interface_table", "maps"]) == 2
    with pytest.raises(ValueError, match="unknown product 'maps'"):
        products.make("out", "maps")
