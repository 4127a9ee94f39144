"""Generated kernels only. DO NOT EDIT: ``python -m distkin.codegen`` writes them."""

__all__: list = []
