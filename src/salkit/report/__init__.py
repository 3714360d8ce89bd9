"""The report layer: after a workflow has computed, it writes every file of the run (datasets,
tables, figures, ``metrics.json``, ``scenario.yaml``) and lays out ``report.html``.

:func:`write_run` takes a :class:`~salkit.systems.result.RunResult`; :func:`run_scenario`
runs a scenario's workflow and writes it.

Modules: :mod:`~salkit.report.run` (writing a run), :mod:`~salkit.report.writers` (each workflow's
figures and page), :mod:`~salkit.report.pages` (templates, the Files and metrics sections),
:mod:`~salkit.report.judge` (measured against theory, the one set of rules),
:mod:`~salkit.report.contexts` (the seed pages' tables), :mod:`~salkit.report.index` (the page of
several runs), :mod:`~salkit.report.docs` (the README's generated blocks).
"""
from .contexts import downlooking_context, table3_cells
from .judge import comparison_rows, headline, passed
from .pages import API_COMMAND, FILE_NOTES, describe_dataset, environment, file_rows, human_size, metric_rows, render
from .run import run_scenario, write_run

__all__ = ["API_COMMAND", "FILE_NOTES", "comparison_rows", "describe_dataset", "downlooking_context", "environment",
           "file_rows", "headline", "human_size", "metric_rows", "passed", "render", "run_scenario", "table3_cells",
           "write_run"]
