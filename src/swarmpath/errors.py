"""Exceptions of swarmpath: one base class, one subclass per kind of bad input.

Every message names where the problem is (file, field or line) and what it is, so that the
command line can print it on one line and exit with code 2.
"""
from __future__ import annotations


class SwarmpathError(Exception):
    """Base class of every error swarmpath raises on purpose (bad input, unknown names)."""


class _Located(Exception):
    """An error in an input document: ``problem`` at the dotted ``field`` (``robots[3].start``)
    of ``source`` (a file name, if any); the message reads ``source: field: problem``."""

    def __init__(self, problem: str, *, field: str | None = None, source: str | None = None):
        self.problem = problem
        self.field = field
        self.source = source
        super().__init__(": ".join([p for p in (source, field) if p] + [problem]))

    def with_source(self, source: str):
        """The same error, attributed to ``source`` (a file name) unless it already is."""
        if self.source:
            return self
        return type(self)(self.problem, field=self.field, source=source)


class ScenarioError(_Located, SwarmpathError):
    """A scenario (file or in-memory description) is malformed or inconsistent."""


class MapFormatError(SwarmpathError):
    """A MovingAI .map or .scen file does not follow the benchmark format."""


class UnknownNameError(SwarmpathError):
    """A registry (planners, controllers, optimisers, ...) has no entry of that name."""


class ConfigError(SwarmpathError):
    """Parameters of an algorithm or a command are invalid (e.g. a negative budget)."""


class SuiteError(_Located, ConfigError):
    """A sweep suite file is malformed or names something that does not exist."""
