"""Experimental datasets from the papers, shipped as CSV package data."""
