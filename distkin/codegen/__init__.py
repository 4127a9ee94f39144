"""Code generation: symbolic models in, numeric kernels out (see :mod:`.emit`)."""

from .emit import FLAVOURS, Kernel, kernel_source, module_source, symbolic_hash

__all__ = ["Kernel", "kernel_source", "module_source", "symbolic_hash", "FLAVOURS"]
