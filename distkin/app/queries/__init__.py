"""One module per family of scene queries (each registers its handlers)."""

__all__: list[str] = []
