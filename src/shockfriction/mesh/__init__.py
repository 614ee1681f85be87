"""Structured blocks of quadrilaterals (mapped quads), planar and axisymmetric geometry."""
