"""Autofocus (phase gradient, minimum entropy): planned; the foundation ships `none`."""
