"""Typed errors of x3dpd.

Every error a user can cause carries enough context to be fixed without a traceback.
The CLI maps them to exit statuses: :class:`DeckError` and :class:`InputError` -> 2,
:class:`UnstableRunError` -> 3.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Pos:
    """1-based line and column of a token in a deck file (0 when unknown)."""

    line: int = 0
    column: int = 0


#: The position of something that has none (a card synthesised by code).
NOWHERE = Pos(0, 0)


class X3dpdError(Exception):
    """Base class of all errors x3dpd raises on purpose."""

    exit_status = 1


class InputError(X3dpdError):
    """Bad input that is not tied to a place in a deck (a bad option, a missing file)."""

    exit_status = 2


class DeckError(InputError):
    """A deck is wrong at a known place.

    Renders as ``FILE:LINE:COL: CARD: message`` -- the one-line form the CLI prints.

    Parameters
    ----------
    message : str
        What was wrong and what was expected.
    path : str
        The deck's file name as the user gave it.
    line, column : int
        1-based position of the offending token (0 when unknown).
    card : str
        The card's canonical name (``"NODE COORDINATES"``), or ``"DECK"`` for the file as a whole.
    """

    def __init__(
        self, message: str, path: str = "<deck>", line: int = 0, column: int = 0, card: str = "DECK"
    ):
        self.message = message
        self.path = path
        self.line = line
        self.column = column
        self.card = card
        super().__init__(str(self))

    def __str__(self) -> str:
        return f"{self.path}:{self.line}:{self.column}: {self.card}: {self.message}"


class UsrfrcError(InputError):
    """A USRFRC force specification or user force file cannot be used."""


class UnstableRunError(X3dpdError):
    """A run stopped because it went unstable; the message is the diagnosis.

    Parameters
    ----------
    message : str
        The diagnosis: what happened, where, the likely cause and a remedy.
    time : float
        Simulated time [s] at which the run stopped.
    step : int
        Step index at which the run stopped.
    node : int
        User node id involved (0 when none).
    """

    exit_status = 3

    def __init__(self, message: str, time: float = 0.0, step: int = 0, node: int = 0):
        self.message = message
        self.time = time
        self.step = step
        self.node = node
        super().__init__(message)


class TraceError(InputError):
    """A trace file cannot be read or would be overwritten."""


class ModeFileError(InputError):
    """A file of modes (a MODAL FILE record's OP2, UFF, CSV or NPZ file) cannot be used.

    Renders as ``FILE:LINE: message`` when the line is known (CSV), else ``FILE: message``.

    Parameters
    ----------
    path : str
        The file as the user gave it.
    message : str
        What was wrong and what was expected.
    line : int
        1-based line of a text file (0 when unknown or not a text file).
    """

    def __init__(self, path, message: str, line: int = 0):
        self.path = str(path)
        self.message = message
        self.line = line
        super().__init__(str(self))

    def __str__(self) -> str:
        where = f"{self.path}:{self.line}" if self.line else self.path
        return f"{where}: {self.message}"
