"""Output folders that are complete or absent, with a manifest that ``salkit verify`` checks.

A run writes into a hidden temporary sibling (``.NAME.tmp-RUNID``) and renames it onto ``NAME``
only when every file is written and ``manifest.json`` lists them with their sizes and SHA-256.
Failure or interruption removes the temporary folder. ``NAME`` must be new or empty unless
``overwrite``, which swaps the old folder out only once the new one is complete. A lock file
(``.NAME.lock``, ``flock``) refuses a second run into the same folder while one is writing.
Paths listed in ``keep_on_failure`` (a stacking checkpoint) are kept in ``.NAME.resume`` on failure
and moved back into the next run's folder, so long work resumes.
"""
from __future__ import annotations

import datetime as _dt
import fcntl
import hashlib
import json
import os
import shutil
import sys
import uuid
from pathlib import Path

from ..errors import DataFileError, EnvironmentProblem, ScenarioError
from ..interrupts import INTERRUPTED, KEPT_FOR_RESUME
from .. import __version__

MANIFEST = "manifest.json"


def sha256_file(path: Path, chunk: int = 1 << 20) -> str:
    """SHA-256 of a file's bytes (hex).

    Parameters
    ----------
    path : path
    chunk : int
        Bytes read at a time.

    Returns
    -------
    str
    """
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        while True:
            b = fh.read(chunk)
            if not b:
                break
            h.update(b)
    return h.hexdigest()


def _files(root: Path):
    for dirpath, dirnames, filenames in os.walk(root):
        dirnames.sort()
        for f in sorted(filenames):
            p = Path(dirpath) / f
            rel = p.relative_to(root).as_posix()
            if rel != MANIFEST:
                yield rel, p


def write_manifest(folder: Path, run_id: str, command: list[str] | None = None) -> dict:
    """Write ``manifest.json`` for every file under ``folder`` (sizes, SHA-256), status "complete".

    Parameters
    ----------
    folder : Path
    run_id : str
    command : list of str, optional
        Command line (default ``sys.argv``).

    Returns
    -------
    dict
        The manifest.
    """
    scen = folder / "scenario.yaml"
    m = {"salkit_manifest": 1, "run_id": run_id, "status": "complete", "salkit_version": __version__,
         "command": list(command if command is not None else sys.argv),
         "created": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
         "scenario_sha256": sha256_file(scen) if scen.is_file() else None,
         "files": [{"path": rel, "size": p.stat().st_size, "sha256": sha256_file(p)} for rel, p in _files(folder)]}
    tmp = folder / f".{MANIFEST}.tmp"
    with open(tmp, "w") as fh:
        json.dump(m, fh, indent=1)
        fh.write("\n")
        fh.flush()
        os.fsync(fh.fileno())
    os.replace(tmp, folder / MANIFEST)
    return m


def verify(folder: str | Path) -> dict:
    """Check a run folder against its manifest.

    Parameters
    ----------
    folder : str or Path

    Returns
    -------
    dict
        ``ok`` (bool), ``problems`` (list of str: missing, resized or changed files, a status other
        than complete), ``extra`` (files not in the manifest) and ``files`` (count checked).

    Raises
    ------
    DataFileError
        No folder, or no readable manifest.
    """
    d = Path(folder)
    if not d.is_dir():
        raise DataFileError(f"{d}: not a folder")
    try:
        m = json.loads((d / MANIFEST).read_text())
        files = m["files"]
    except FileNotFoundError:
        raise DataFileError(f"{d}: no {MANIFEST} (not a salkit run folder, or an unfinished one)") from None
    except (ValueError, KeyError, TypeError) as e:
        raise DataFileError(f"{d}/{MANIFEST}: unreadable ({type(e).__name__}: {e})") from None
    problems = []
    if m.get("status") != "complete":
        problems.append(f"status is {m.get('status')!r}, not 'complete'")
    listed = set()
    for f in files:
        rel = f["path"]
        listed.add(rel)
        p = d / rel
        if not p.is_file():
            problems.append(f"{rel}: missing")
        elif p.stat().st_size != f["size"]:
            problems.append(f"{rel}: {p.stat().st_size} bytes, manifest says {f['size']}")
        elif sha256_file(p) != f["sha256"]:
            problems.append(f"{rel}: SHA-256 differs from the manifest (changed or corrupted)")
    extra = [rel for rel, _ in _files(d) if rel not in listed]
    return {"ok": not problems, "problems": problems, "extra": extra, "files": len(files)}


class RunFolder:
    """Context manager: yields a temporary folder that becomes ``out`` on success.

    Parameters
    ----------
    out : str or Path
        The output folder: new, or an empty folder, or any folder with ``overwrite``.
    overwrite : bool
        Replace an existing non-empty folder (only once the new one is complete).
    keep_on_failure : tuple of str
        Names inside the folder kept in ``.NAME.resume`` when the run fails, and restored into the
        next run's temporary folder.
    command : list of str, optional
        Command line recorded in the manifest.

    Raises
    ------
    ScenarioError
        ``out`` empty, the current folder or above it, an existing file, or a non-empty folder
        without ``overwrite``.
    EnvironmentProblem
        Another run holds the folder's lock, or the folder cannot be created.
    """

    def __init__(self, out, *, overwrite: bool = False, keep_on_failure: tuple = (), command=None):
        if out is None or str(out).strip() == "":
            raise ScenarioError("--out", str(out) if out is not None else None, "must name a folder")
        self.out = Path(out).absolute()
        cwd = Path.cwd().resolve()
        res = self.out.resolve()
        if res == cwd or res in cwd.parents or res == Path(res.anchor):
            raise ScenarioError("--out", str(out), "must be a new or empty folder, not the current folder, one "
                                "above it or the root")
        self.overwrite, self.keep, self.command = overwrite, tuple(keep_on_failure), command
        self.run_id = uuid.uuid4().hex[:12]
        self.parent = self.out.parent
        self.name = self.out.name
        self.tmp = self.parent / f".{self.name}.tmp-{self.run_id}"
        self.resume = self.parent / f".{self.name}.resume"
        self._lock_fh = None

    def _check_target(self):
        if self.out.is_file() or (self.out.exists() and not self.out.is_dir()):
            raise ScenarioError("--out", str(self.out), "names an existing file; give a folder")
        if self.out.is_dir() and any(self.out.iterdir()) and not self.overwrite:
            n = sum(1 for _ in self.out.iterdir())
            raise ScenarioError("--out", str(self.out), f"holds {n} entries; choose a new or empty folder, or "
                                "pass --overwrite to replace it once the new run is complete")

    def __enter__(self) -> Path:
        self._check_target()
        try:
            self.parent.mkdir(parents=True, exist_ok=True)
            lock = self.parent / f".{self.name}.lock"
            self._lock_fh = open(lock, "a+")
        except OSError as e:
            raise EnvironmentProblem(f"cannot create the output folder {self.out}: {e.strerror or e}") from None
        try:
            fcntl.flock(self._lock_fh.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            self._lock_fh.seek(0)
            who = self._lock_fh.read().strip() or "another process"
            self._lock_fh.close()
            self._lock_fh = None
            raise EnvironmentProblem(f"{self.out}: another salkit run ({who}) is writing into this folder; "
                                     "wait for it or choose another --out") from None
        self._lock_fh.seek(0)
        self._lock_fh.truncate()
        self._lock_fh.write(f"pid {os.getpid()}, run {self.run_id}")
        self._lock_fh.flush()
        try:
            self._check_target()  # the other run may have finished while we waited
            self.tmp.mkdir()
            if self.resume.is_dir():
                for p in self.resume.iterdir():
                    os.replace(p, self.tmp / p.name)
                self.resume.rmdir()
        except BaseException:
            self._cleanup(False)
            raise
        return self.tmp

    def discard_resume(self) -> None:
        """Forget what an interrupted run kept for resuming (``.NAME.resume``): the next run starts
        afresh."""
        shutil.rmtree(self.resume, ignore_errors=True)

    def adopt_stale(self, name: str) -> None:
        """Inside the block: move ``name`` of runs killed without cleaning up (stale ``.NAME.tmp-*``
        folders; their lock is free, since this run holds it now) into this run's folder, entry by
        entry, and remove the stale folders.

        Parameters
        ----------
        name : str
            A folder inside the run folder (a checkpoint).
        """
        dst = self.tmp / name
        for stale in sorted(self.parent.glob(f".{self.name}.tmp-*")):
            if stale == self.tmp or not (stale / name).is_dir():
                continue
            dst.mkdir(exist_ok=True)
            for p in (stale / name).iterdir():
                if not (dst / p.name).exists():
                    os.replace(p, dst / p.name)
            shutil.rmtree(stale, ignore_errors=True)

    def _cleanup(self, success: bool):
        if not success and self.tmp.exists():
            kept = [n for n in self.keep if (self.tmp / n).exists()]
            if kept:
                self.resume.mkdir(exist_ok=True)
                for n in kept:
                    if (self.resume / n).exists():
                        shutil.rmtree(self.resume / n, ignore_errors=True)
                    os.replace(self.tmp / n, self.resume / n)
                KEPT_FOR_RESUME.update(resume=str(self.resume), out=str(self.parent / self.name))
            shutil.rmtree(self.tmp, ignore_errors=True)
        if self._lock_fh is not None:
            try:
                os.unlink(self.parent / f".{self.name}.lock")
            except OSError:
                pass
            fcntl.flock(self._lock_fh.fileno(), fcntl.LOCK_UN)
            self._lock_fh.close()
            self._lock_fh = None

    def __exit__(self, exc_type, exc, tb):
        if exc_type is not None:
            self._cleanup(False)
            return False
        if INTERRUPTED["signal"] is not None:
            self._cleanup(False)
            raise KeyboardInterrupt(f"signal {INTERRUPTED['signal']}")
        try:
            write_manifest(self.tmp, self.run_id, self.command)
            fd = os.open(self.tmp, os.O_RDONLY)
            try:
                os.fsync(fd)
            finally:
                os.close(fd)
            old = None
            if self.out.is_dir():
                if any(self.out.iterdir()):
                    old = self.parent / f".{self.name}.old-{self.run_id}"
                    os.rename(self.out, old)
                else:
                    self.out.rmdir()
            os.rename(self.tmp, self.out)
            if old is not None:
                shutil.rmtree(old, ignore_errors=True)
        except BaseException as e:
            self._cleanup(False)
            if isinstance(e, OSError):
                raise EnvironmentProblem(f"cannot finish the output folder {self.out}: "
                                         f"{os.strerror(e.errno) if e.errno else e}") from None
            raise
        self._cleanup(True)
        return False


__all__ = ["INTERRUPTED", "MANIFEST", "RunFolder", "sha256_file", "verify", "write_manifest"]


def is_staging(path: str | Path) -> bool:
    """Whether ``path`` is the temporary folder of a :class:`RunFolder` (``.NAME.tmp-RUNID``),
    which gets a ``manifest.json`` when the run completes.

    Parameters
    ----------
    path : path

    Returns
    -------
    bool

    Examples
    --------
    >>> is_staging("results/.spotlight.tmp-20261123T150000-ab12"), is_staging("results/spotlight")
    (True, False)
    """
    name = Path(path).name
    return name.startswith(".") and ".tmp-" in name
