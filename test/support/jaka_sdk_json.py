"""How JAKA's C++ SDK (libjakaAPI 2.1.14) writes requests and reads JSON: its old jsoncpp's
strict conversions, for the test model of JAKA's software (:mod:`jaka_sdk_model`; the facts are
in docs/protocol.md).

* ``asString`` on a number, ``asDouble``/``asInt`` on a string throw, and nothing in the SDK
  catches them: the client process aborts (:class:`SdkCrash`); indexing a scalar or an object as
  an array is a segmentation fault (:class:`SdkCrash`);
* ``asBool`` of any non-empty string is true (``"false"`` reads true); ``asInt`` truncates a
  double and takes a bool;
* a missing key reads 0 / false / ""; a short array reads zeros for what is missing.
* Requests are compact JSON with sorted keys, doubles with 16 significant digits or a fixed 2
  decimals for some fields.
"""
from __future__ import annotations

import json
import math
from typing import Any, Dict, List, Optional

class SdkCrash(AssertionError):
    """JAKA's SDK would abort (an uncaught jsoncpp exception) or segfault on this reply."""


class SdkGarbage(AssertionError):
    """JAKA's SDK would go on with a value read wrong."""


# ---- jsoncpp's conversions, as strict as the SDK's ------------------------------------------

def as_string(v: Any) -> str:
    if v is None:
        return ""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return v
    raise SdkCrash(f"asString on {v!r}: 'Type is not convertible to string'")


def as_double(v: Any) -> float:
    if v is None:
        return 0.0
    if isinstance(v, (bool, int, float)):
        return float(v)
    raise SdkCrash(f"asDouble on {v!r}: 'Value is not convertible to double'")


def as_int(v: Any) -> int:
    if v is None:
        return 0
    if isinstance(v, (bool, int, float)):
        return int(v)
    raise SdkCrash(f"asInt on {v!r}: 'Value is not convertible to Int'")


def as_bool(v: Any) -> bool:
    if v is None:
        return False
    if isinstance(v, str):
        return v != ""          # "false" reads as true
    if isinstance(v, (bool, int, float)):
        return bool(v)
    raise SdkCrash(f"asBool on {v!r}")


def member(obj: Any, key: str) -> Any:
    """``obj[key]``: None when missing; an object is required (or null)."""
    if obj is None:
        return None
    if not isinstance(obj, dict):
        raise SdkCrash(f"operator[]({key!r}) on {type(obj).__name__}: requires an object")
    return obj.get(key)


def element(arr: Any, i: int) -> Any:
    """``arr[i]``: None past the end; indexing a scalar or an object crashes."""
    if arr is None:
        return None
    if not isinstance(arr, list):
        raise SdkCrash(f"operator[]({i}) on {type(arr).__name__}: SIGSEGV")
    return arr[i] if i < len(arr) else None


def doubles(arr: Any, n: int) -> List[float]:
    return [as_double(element(arr, i)) for i in range(n)]


# ---- requests as the SDK writes them -----------------------------------------------------------

def _number(x: float, decimals: Optional[int]) -> str:
    if decimals is not None:
        return f"{x:.{decimals}f}"
    text = "%.16g" % x
    return text if any(c in text for c in ".en") else text + ".0"


def sdk_json(obj: Any, fixed: Dict[str, int], key: str = "") -> str:
    """Compact JSON with sorted keys; doubles with 16 significant digits, or ``fixed[key]``
    decimals for the fields the SDK writes so (``"rate_value":0.50``, ``"mass":1.50``)."""
    if isinstance(obj, dict):
        return "{" + ",".join(f"{json.dumps(k)}:{sdk_json(obj[k], fixed, k)}"
                              for k in sorted(obj)) + "}"
    if isinstance(obj, (list, tuple)):
        return "[" + ",".join(sdk_json(v, fixed, key) for v in obj) + "]"
    if isinstance(obj, float):
        return _number(obj, fixed.get(key))
    return json.dumps(obj)


#: fields the SDK writes with fixed decimals (seen: "rate_value":0.50, "mass":1.50, "tol":0.50,
#: "circle_cnt":1.50, "value_new":2.50, "ftReboundFK":0.250)
FIXED_DECIMALS = {"rate_value": 2, "mass": 2, "tol": 2, "circle_cnt": 2, "value_new": 2,
                  "ftReboundFK": 3, "xyz_interval": 2, "rpy_interval": 2}


def deg(values) -> List[float]:
    return [float(math.degrees(v)) for v in values]


def pose_deg(pose) -> List[float]:
    return [float(v) for v in pose[:3]] + deg(pose[3:])


def pose_rad(pose) -> List[float]:
    return [as_double(v) for v in pose[:3]] + [math.radians(as_double(v)) for v in pose[3:]]
