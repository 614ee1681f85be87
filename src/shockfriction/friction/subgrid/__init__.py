"""Sub-grid interface models: a 1D implicit column under each slide-line node (thesis ch. 7-8)."""
