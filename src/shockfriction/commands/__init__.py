"""Command modules: each defines ``register(app)`` adding its typer command(s)."""
