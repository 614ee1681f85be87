"""The thesis's analyses (dimensionless numbers, stability limit) and exact solutions for verification."""
