"""Fixtures of the integration layer: the one emulator a module's tests share
(:func:`support.emulated_arm.emu`; a module sets ``EMULATOR`` for other options)."""
from support.emulated_arm import emu  # noqa: F401 - the fixture

__all__ = ["emu"]
