"""The ``bigym`` command line: the only layer that knows every other (tasks, demos, experts, policies).

``app.py`` holds the root command (tasks, run, props); ``demos.py`` the ``bigym demos`` group.
"""

from bigym.cli.app import app, main, task_class

__all__ = ["app", "main", "task_class"]
