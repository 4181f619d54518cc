"""The exceptions semfuse raises. The native module raises these classes (it looks them up here)."""
from __future__ import annotations

__all__ = ["Error", "ServerError", "ClientError", "CallTimeout"]


class Error(Exception):
    """A semfuse call failed.

    Attributes:
        reason: the kind of failure, for code to switch on: ``"invalid_argument"``,
            ``"not_found"``, ``"too_large"``, ``"unavailable"``, ``"internal"`` or
            ``"unspecified"``. The message (``str(error)``) is for people.
    """

    def __init__(self, message: str, reason: str = "unspecified") -> None:
        super().__init__(message)
        self.reason = reason


class ServerError(Error):
    """The server answered with an error: ``str(error)`` is its message, ``reason`` its kind.

    Attributes:
        status: the reply's status code on the wire (1 invalid argument, 2 not found,
            3 unavailable, 4 internal, 5 too large).
    """

    def __init__(self, message: str, reason: str = "unspecified", status: int = 0) -> None:
        super().__init__(message, reason)
        self.status = status


class ClientError(Error):
    """The request could not be sent, or the server's reply could not be decoded."""


class CallTimeout(Error, TimeoutError):
    """No server was matched, or no reply came in time. Also a built-in ``TimeoutError``."""

    def __init__(self, message: str, reason: str = "unavailable") -> None:
        super().__init__(message, reason)
