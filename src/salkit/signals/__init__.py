"""Waveforms, windows, receivers and noise."""
