"""Built-in scenes run by ``distkin demo`` (package data)."""

__all__: list = []
