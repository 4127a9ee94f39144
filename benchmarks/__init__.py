"""distkin benchmarks: ``python -m benchmarks [NAME ...]`` (see ``__main__``)."""
