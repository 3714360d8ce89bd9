"""Sphinx configuration of salkit's API reference, built from the docstrings (numpydoc style, read by
napoleon). ``make api`` builds it into ``docs/api/_build/html`` with warnings as errors; CI runs it."""
import salkit

project = "salkit"
author = "the salkit developers"
release = salkit.__version__
extensions = ["sphinx.ext.autodoc", "sphinx.ext.autosummary", "sphinx.ext.napoleon", "sphinx.ext.mathjax"]
autosummary_generate = True
autosummary_imported_members = False
# each object documented where it is defined (a package's re-exports are not documented twice)
autodoc_default_options = {"members": True, "undoc-members": False, "show-inheritance": False,
                           "ignore-module-all": True}
autodoc_typehints = "none"  # signatures show their hints; the numpydoc sections give types and units
napoleon_numpy_docstring = True
napoleon_google_docstring = False
napoleon_use_rtype = False
napoleon_use_param = False  # types as written (plain text), not cross-references: short names repeat
napoleon_use_ivar = True
napoleon_custom_sections = [("Yields", "returns_style")]
# plain-text types ("ndarray, shape (P, 3)") name words that several classes hold as attributes:
# ambiguous cross-references, not broken documentation
suppress_warnings = ["autosummary.import_cycle", "ref.python"]
exclude_patterns = ["_build"]
html_theme = "alabaster"
nitpicky = False


def _plain_bars(app, what, name, obj, options, lines):
    """Docstrings write magnitudes as |x| (plain-text mathematics); in reST a bar opens a substitution,
    so each is escaped."""
    for i, line in enumerate(lines):
        if "|" in line and not line.lstrip().startswith(("+", "|=")):
            lines[i] = line.replace("|", "\\|")


def setup(app):
    app.connect("autodoc-process-docstring", _plain_bars)
