"""A GPU resource shared by a layer and its ``fresh()`` copies (``Sky.at``): the first holder
makes it, each copy prepared on the same context takes it, and the last holder to be
released frees it."""

from __future__ import annotations

__all__ = ["SharedResource"]


class SharedResource:
    """``resource`` (anything with ``release()``), made on ``ctx``, held by ``refs`` owners."""

    def __init__(self, resource, ctx):
        self.resource = resource
        self.ctx = ctx
        self.refs = 1

    def serves(self, ctx) -> bool:
        """Whether the resource is still alive and on ``ctx``."""
        return self.resource is not None and self.ctx is ctx

    def take(self):
        """One holder more: the resource."""
        self.refs += 1
        return self.resource

    def drop(self) -> None:
        """One holder fewer; the last one releases the resource."""
        self.refs -= 1
        if self.refs <= 0 and self.resource is not None:
            self.resource.release()
            self.resource = None
