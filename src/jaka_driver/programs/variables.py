"""User variables, as a controller keeps them: numbered (``id``), named (``alias``), each holding
a number (``value``) — what JAKA's SDK reads with ``get_user_var`` and sets with
``set_user_var`` (``query_user_defined_variable`` / ``modify_user_defined_variable``).

A program declares the variables it uses (``var <id> <alias> = <value>``); loading it sets them
to their declared values and keeps every other. A program refers to a variable by its id, so a
rename from outside does not break it. Thread-safe.
"""
from __future__ import annotations

import math
import threading
from typing import Dict, Iterable, List, Tuple

from ..backend.programs import UserVariable
from ..common.results import Code, Result

#: the longest alias kept, characters
MAX_ALIAS = 100


class UserVariables:
    def __init__(self):
        self._lock = threading.Lock()
        self._table: Dict[int, Tuple[float, str]] = {}

    def declare(self, declarations: Iterable) -> None:
        """Set each declared variable (``id``, ``alias``, ``value``) as its program says."""
        with self._lock:
            for d in declarations:
                self._table[d.id] = (float(d.value), d.alias)

    def values(self) -> Dict[int, float]:
        """id → value, a copy."""
        with self._lock:
            return {k: v for k, (v, _) in self._table.items()}

    def listed(self) -> List[UserVariable]:
        with self._lock:
            return [UserVariable(k, v, a) for k, (v, a) in sorted(self._table.items())]

    def assign(self, var_id: int, value: float) -> None:
        """A program's ``set``: the value, the name kept."""
        with self._lock:
            self._table[var_id] = (float(value), self._table[var_id][1])

    def set(self, var_id: int, value: float, alias: str) -> Result:
        """From outside: variable ``var_id`` (it must exist) takes ``value`` (finite) and, unless
        ``alias`` is empty, the name ``alias`` (at most :data:`MAX_ALIAS` characters)."""
        if not math.isfinite(value):
            return Result.failure(Code.INVALID_PARAMETER, f"value is {value}, expected a "
                                  "finite number")
        if len(alias) > MAX_ALIAS:
            return Result.failure(Code.INVALID_PARAMETER, f"alias has {len(alias)} "
                                  f"characters, at most {MAX_ALIAS}")
        with self._lock:
            if var_id not in self._table:
                known = ", ".join(str(k) for k in sorted(self._table)) or "none (a loaded " \
                    "program declares them)"
                return Result.failure(Code.INVALID_PARAMETER, f"id is {var_id}, not a user "
                                      f"variable (ids: {known})")
            name = alias or self._table[var_id][1]
            self._table[var_id] = (float(value), name)
        return Result.success(f"user variable {var_id} ({name}) = {value:g}")

    def clear(self) -> None:
        with self._lock:
            self._table.clear()
