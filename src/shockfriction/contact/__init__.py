"""Slide lines: pairing, unilateral contact and the friction step (thesis section 3.3)."""
