"""Multi-scale friction: the sub-grid columns coupled under every slide-line node (thesis Part III)."""
