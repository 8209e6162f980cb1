"""bigym's optional compiled step path (bigym/_hotloop.c); everything else is in pyproject.toml.

Optional: without a C compiler the install goes on and env.step runs its Python code,
which gives the same results, only slower (bigym.hotloop.AVAILABLE says which).
"""

import sys

from setuptools import Extension, setup

# No fused multiply-add: the C code must round exactly where the Python code does.
FLAGS = ["/fp:precise"] if sys.platform == "win32" else ["-O2", "-ffp-contract=off"]

setup(ext_modules=[Extension("bigym._hotloop", ["bigym/_hotloop.c"], optional=True, extra_compile_args=FLAGS)])
