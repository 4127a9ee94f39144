"""The application: scenes, the query registry, reports, the command line."""

__all__: list[str] = []
