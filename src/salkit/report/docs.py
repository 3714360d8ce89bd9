"""What the README quotes from a run of every example, made from the run itself: the figures'
captions with their numbers, the list of files each example writes, and the pictures.

``make docs-figures`` (``docs/make_figures.py``) runs every example and rewrites the README's
generated blocks, each between ``<!-- generated:NAME -->`` and ``<!-- /generated:NAME -->``; a
test compares those blocks with a fresh ``make demo`` so that the README never drifts from what
the code computes.
"""
from __future__ import annotations

import json
import re
import shutil
from pathlib import Path

from ..errors import DataFileError
from ..focus.formers import former_table
from ..metrics.table import metrics_table

#: Figures of a results folder copied into docs/images (source, destination name).
FIGURES = (("spotlight_points/image.png", "spotlight_points_image.png"),
           ("spotlight_points/cuts.png", "spotlight_points_cuts.png"),
           ("downlooking_3d/terrain.png", "downlooking_terrain.png"),
           ("downlooking_3d/scene.png", "downlooking_scene.png"),
           ("downlooking_3d/disturbance.png", "downlooking_disturbance.png"),
           ("stripmap_scene/image.png", "stripmap_scene_image.png"),
           ("sweep_turbulence_cn2/sweep_peak_amplitude.png", "sweep_turbulence_cn2_peak.png"),
           ("vehicle_turbulence/model.png", "vehicle_model.png"), ("vehicle_turbulence/image.png", "vehicle_image.png"))

_BLOCK = re.compile(r"(<!-- generated:(?P<name>[a-z_]+) -->\n)(?P<body>.*?)(<!-- /generated:(?P=name) -->)", re.S)


def _metrics(results: Path, name: str) -> dict:
    return json.loads((results / name / "metrics.json").read_text())


def spotlight_caption(m: dict) -> str:
    """The README's caption of the spotlight figures, with the run's numbers.

    Parameters
    ----------
    m : dict
        Metrics of ``examples/spotlight_points.yaml``.

    Returns
    -------
    str
    """
    return ("*`examples/spotlight_points.yaml`: five point targets at 5 km, 2 cm x 2 cm resolution, polar\n"
            "format. Red circles: where the geometry says the targets are. Below, the cuts through the\n"
            f"brightest target against the theoretical sinc (IRW {m['irw_range_m'] * 100:.3f} cm vs "
            f"{m['irw_range_theory_m'] * 100:.3f} cm in range, PSLR {m['pslr_range_db']:.2f} dB;\n"
            f"azimuth {m['irw_azimuth_m'] * 100:.3f} cm vs {m['irw_azimuth_theory_m'] * 100:.3f} cm, "
            f"{m['pslr_azimuth_db']:.2f} dB).*\n")


def downlooking_caption(m: dict) -> str:
    """The README's caption of the down-looking terrain figure, with the run's numbers.

    Parameters
    ----------
    m : dict
        Metrics of ``examples/downlooking_3d.yaml``.

    Returns
    -------
    str
    """
    return ("*`examples/downlooking_3d.yaml` (seed 000): a terrain seen at "
            f"{m['terrain_look_angle_deg']:g} deg by the self-interferometric\n"
            "down-looking SAL, simulated from the optical fields. The interferogram's fringes stay straight\n"
            "(upper right): the fringe phase is a function of the image coordinate itself, so it gains "
            f"{abs(m['terrain_phase_per_height_rad_per_m']):.3f}\n"
            f"rad per metre of height against the {m['terrain_phase_per_height_model_rad_per_m']:.1f} rad/m that "
            "the paper's projection picture implies (lower\n"
            f"middle), and the height recovered from the fringes is flat (RMS "
            f"{m['terrain_height_recovered_rms_m'] * 1000:.1f} mm against the terrain's "
            f"{m['terrain_height_rms_m'] * 1000:.0f} mm;\nlower right). See docs/downlooking.md.*\n")


def files_table(results: Path) -> str:
    """A Markdown table of the files each example's run folder holds.

    Parameters
    ----------
    results : path
        A ``make demo`` results folder.

    Returns
    -------
    str
    """
    rows = ["| example | files its run writes (besides report.html, metrics.json, scenario.yaml, manifest.json) |",
            "|---|---|"]
    common = {"report.html", "metrics.json", "scenario.yaml", "manifest.json"}
    for d in sorted(p for p in Path(results).iterdir() if p.is_dir() and not p.name.startswith(".")):
        names = sorted(p.name + ("/" if p.is_dir() else "") for p in d.iterdir()
                       if not p.name.startswith(".") and p.name not in common)
        nc = [n for n in names if n.endswith((".nc", "/"))]
        png = [n for n in names if n.endswith(".png")]
        csv = [n for n in names if n.endswith(".csv")]
        parts = []
        if nc:
            parts.append(", ".join(f"`{n}`" for n in nc))
        if png:
            parts.append(", ".join(f"`{n}`" for n in png))
        if csv:
            parts.append(f"{len(csv)} CSV tables" if len(csv) > 4 else ", ".join(f"`{n}`" for n in csv))
        rows.append(f"| `{d.name}` | {'; '.join(parts)} |")
    return "\n".join(rows) + "\n"


def blocks(results: str | Path) -> dict:
    """Every generated block of the README, from a results folder of ``make demo``.

    Parameters
    ----------
    results : path

    Returns
    -------
    dict
        Block name -> text (the table of formers from their declarations).
    """
    results = Path(results)
    return {"spotlight_caption": spotlight_caption(_metrics(results, "spotlight_points")),
            "downlooking_caption": downlooking_caption(_metrics(results, "downlooking_3d")),
            "files": files_table(results), "formers": former_table()}


def declared_blocks() -> dict:
    """docs/metrics.md's generated block: the table of metrics, from the declarations.

    Returns
    -------
    dict
        Block name -> text.
    """
    return {"metrics": metrics_table()}


def read_blocks(text: str) -> dict:
    """The generated blocks of a README's text.

    Parameters
    ----------
    text : str

    Returns
    -------
    dict
        Block name -> text.
    """
    return {m.group("name"): m.group("body") for m in _BLOCK.finditer(text)}


def fill(text: str, new: dict) -> str:
    """``text`` with each generated block replaced by ``new[name]``.

    Parameters
    ----------
    text : str
    new : dict

    Returns
    -------
    str

    Raises
    ------
    DataFileError
        When a block of ``new`` has no markers in ``text``.

    Examples
    --------
    >>> fill("a\\n<!-- generated:x -->\\nold\\n<!-- /generated:x -->\\nb", {"x": "new\\n"})
    'a\\n<!-- generated:x -->\\nnew\\n<!-- /generated:x -->\\nb'
    """
    missing = set(new) - set(read_blocks(text))
    if missing:
        raise DataFileError(f"README has no generated block(s) {sorted(missing)}: add "
                            "<!-- generated:NAME --> and <!-- /generated:NAME --> markers")
    return _BLOCK.sub(lambda m: m.group(1) + new.get(m.group("name"), m.group("body")) + m.group(4), text)


def copy_figures(results: str | Path, images: str | Path) -> list[Path]:
    """Copy the README's and docs' figures (:data:`FIGURES`) from a results folder.

    Parameters
    ----------
    results, images : path

    Returns
    -------
    list of Path
        The files written.
    """
    out = []
    Path(images).mkdir(parents=True, exist_ok=True)
    for src, dst in FIGURES:
        p = Path(images) / dst
        shutil.copyfile(Path(results) / src, p)
        out.append(p)
    return out
