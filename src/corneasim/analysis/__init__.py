"""Curve fits, puncture detection, validation against experiments."""
