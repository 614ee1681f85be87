"""TOML decks -> validated pydantic models.  The deck layer does no physics."""

from shockfriction.deck.base import DeckModel, format_validation_error, load_deck, read_toml

__all__ = ["DeckModel", "format_validation_error", "load_deck", "read_toml"]
