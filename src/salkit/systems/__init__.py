"""Seed systems as compositions of the lower layers."""
