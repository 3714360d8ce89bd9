"""Run folders are complete or absent; manifests; the lock."""
import json

import pytest

from salkit.errors import EnvironmentProblem, ScenarioError
from salkit.io.runfolder import RunFolder, verify


def _siblings(tmp_path):
    return sorted(p.name for p in tmp_path.iterdir())


def test_success_renames_into_place_with_manifest(tmp_path):
    with RunFolder(tmp_path / "out") as d:
        (d / "a.txt").write_text("x")
        (d / "sub").mkdir()
        (d / "sub" / "b.bin").write_bytes(b"\0" * 10)
        assert not (tmp_path / "out").exists()  # nothing visible until complete
    assert _siblings(tmp_path) == ["out"]
    m = json.loads((tmp_path / "out" / "manifest.json").read_text())
    assert m["status"] == "complete" and {f["path"] for f in m["files"]} == {"a.txt", "sub/b.bin"}
    assert verify(tmp_path / "out")["ok"]
    (tmp_path / "out" / "a.txt").write_text("y")
    r = verify(tmp_path / "out")
    assert not r["ok"] and "a.txt: SHA-256 differs" in r["problems"][0]


def test_failure_leaves_nothing(tmp_path):
    with pytest.raises(RuntimeError):
        with RunFolder(tmp_path / "out") as d:
            (d / "a.txt").write_text("x")
            raise RuntimeError("boom")
    assert _siblings(tmp_path) == []
    with pytest.raises(KeyboardInterrupt):
        with RunFolder(tmp_path / "out") as d:
            (d / "a.txt").write_text("x")
            raise KeyboardInterrupt
    assert _siblings(tmp_path) == []


def test_existing_folder_needs_overwrite_and_survives_a_failed_overwrite(tmp_path):
    with RunFolder(tmp_path / "out") as d:
        (d / "old.txt").write_text("old")
    with pytest.raises(ScenarioError, match="holds 2 entries"):
        RunFolder(tmp_path / "out").__enter__()
    with pytest.raises(RuntimeError):
        with RunFolder(tmp_path / "out", overwrite=True) as d:
            (d / "new.txt").write_text("new")
            raise RuntimeError
    assert (tmp_path / "out" / "old.txt").read_text() == "old" and verify(tmp_path / "out")["ok"]
    with RunFolder(tmp_path / "out", overwrite=True) as d:
        (d / "new.txt").write_text("new")
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == ["manifest.json", "new.txt"]
    assert _siblings(tmp_path) == ["out"]


def test_empty_existing_folder_is_used(tmp_path):
    (tmp_path / "out").mkdir()
    with RunFolder(tmp_path / "out") as d:
        (d / "a").write_text("1")
    assert (tmp_path / "out" / "a").is_file()


@pytest.mark.parametrize("bad", ["", ".", "file"])
def test_bad_targets_refused(tmp_path, monkeypatch, bad):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "file").write_text("x")
    with pytest.raises(ScenarioError):
        RunFolder(bad).__enter__()


def test_second_writer_is_refused(tmp_path):
    with RunFolder(tmp_path / "out") as d:
        (d / "a").write_text("1")
        with pytest.raises(EnvironmentProblem, match="another salkit run"):
            RunFolder(tmp_path / "out").__enter__()
    assert verify(tmp_path / "out")["ok"]


def test_checkpoint_kept_for_resume(tmp_path):
    with pytest.raises(RuntimeError):
        with RunFolder(tmp_path / "out", keep_on_failure=("stack.zarr",)) as d:
            (d / "stack.zarr").mkdir()
            (d / "stack.zarr" / "chunk").write_text("done 2 of 6")
            (d / "other").write_text("x")
            raise RuntimeError
    assert _siblings(tmp_path) == [".out.resume"]
    with RunFolder(tmp_path / "out", keep_on_failure=("stack.zarr",)) as d:
        assert (d / "stack.zarr" / "chunk").read_text() == "done 2 of 6"
        assert not (d / "other").exists()
    assert _siblings(tmp_path) == ["out"]


def test_adopt_stale_and_discard_resume(tmp_path):
    """A run killed without cleaning up leaves .NAME.tmp-*: the next run adopts the named entries
    it lacks and removes the stale folder; discard_resume forgets a kept checkpoint."""
    out = tmp_path / "o"
    stale = tmp_path / ".o.tmp-deadbeef0000"
    (stale / "checkpoint").mkdir(parents=True)
    (stale / "checkpoint" / "p0.json").write_text("old")
    (stale / "checkpoint" / "p1.json").write_text("old")
    folder = RunFolder(out)
    with folder as tmp:
        (tmp / "checkpoint").mkdir()
        (tmp / "checkpoint" / "p1.json").write_text("new")
        folder.adopt_stale("checkpoint")
        assert sorted(p.name for p in (tmp / "checkpoint").iterdir()) == ["p0.json", "p1.json"]
        assert (tmp / "checkpoint" / "p1.json").read_text() == "new"  # what this run has stays
    assert not stale.exists()
    (tmp_path / ".x.resume").mkdir()
    RunFolder(tmp_path / "x").discard_resume()
    assert not (tmp_path / ".x.resume").exists()
