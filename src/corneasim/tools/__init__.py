"""Rigid instruments (needle, trephine) and their prescribed motion."""
