"""The names of the generated RSS kernels and their flavours (table in
:mod:`distkin.mechanisms.kernels`), shared by the code generator
(:mod:`distkin.codegen.rss`) and the loader, which import nothing else of each other."""

__all__ = ["KERNELS", "FLAVOURS", "ARB_KERNELS", "LOOP_KERNELS", "RANGE_KERNEL"]

KERNELS = ("ik", "reach", "jacobian", "jq_jx", "closure")
FLAVOURS = ("batched", "scalar")
#: the kernels of the certified (arb) flavour, in their own module ``rss_<name>_arb``
ARB_KERNELS = ("ik", "reach", "jq_jx", "closure")
#: the range margins of the revolute legs with a joint range (:mod:`.symbolic`), an arb
#: kernel derived only for a leg table that has such a leg (the certified workspace's;
#: no preset has one)
RANGE_KERNEL = "ranges"
#: the kernels whose batched flavour comes with a ``loop`` twin (suffix ``_loop``): the
#: study's per-pose kinematics, compiled by numba (:mod:`distkin.indices.study_compiled`)
LOOP_KERNELS = ("reach", "jq_jx")
_SUFFIX = {"batched": "", "scalar": "_scalar", "loop": "_loop", "arb": "_arb"}
