"""Matplotlib figures (Agg backend; files, never windows)."""
