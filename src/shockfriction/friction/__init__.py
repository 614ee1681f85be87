"""Friction laws and the sub-grid interface models."""
