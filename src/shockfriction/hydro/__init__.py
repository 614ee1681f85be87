"""2D explicit Lagrangian hydrocode (Wilkins staggered quads), planar and axisymmetric (thesis ch. 3)."""
