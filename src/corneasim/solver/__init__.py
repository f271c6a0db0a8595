"""Explicit dynamics: model and state, element kernels, loads, deletion, time integration."""
