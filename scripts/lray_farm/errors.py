"""The one error type: a message for the user, printed as 'farm: MESSAGE'."""
from __future__ import annotations


class FarmError(Exception):
    """Refuses the command before anything is submitted (or says why it stopped)."""

    def __init__(self, message: str, status: int = 2) -> None:
        super().__init__(message)
        self.status = status
