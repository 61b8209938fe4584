"""``ClosesOnExit``: the one ``with`` protocol of objects that hold a resource until closed."""

from __future__ import annotations

from types import TracebackType
from typing import Self


class ClosesOnExit:
    """Mixin for objects with an idempotent :meth:`close`: ``with obj:`` closes it however the
    block ends. Subclasses override :meth:`close`."""

    def close(self) -> None:
        """Release what the object holds. Idempotent."""

    def __enter__(self) -> Self:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()
