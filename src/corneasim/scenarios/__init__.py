"""Scenario configuration schema and the built-in scenarios (needle, trephine)."""
