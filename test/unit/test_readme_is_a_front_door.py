"""README.md is the front door: short, true about what the driver serves, and pointing at the
documents that hold the detail.

Its first sentence names every series of arms the driver serves (the series are the model ids'
prefixes: zu, c, pro, s, a, minicobo), every model id it names exists, it names every model, and
it stays short enough to read (the full tables live in docs/interface.md and the other documents).
"""
from __future__ import annotations

import re
from pathlib import Path

from jaka_driver.common.models import MODEL_NAMES

ROOT = Path(__file__).resolve().parents[2]
README = (ROOT / "README.md").read_text()
#: what a front door may take; the detail belongs in docs/
MAX_LINES = 300
#: series name as the README writes it → the prefix of its model ids
SERIES = {"Zu": "zu", "C": "c", "Pro": "pro", "S": "s", "A": "a", "MiniCobo": "minicobo"}


def _series_of(model: str) -> str:
    return re.match(r"[a-z]+", model).group(0)


def _first_sentence() -> str:
    body = README.split("\n\n", 1)[1]           # after the title
    return " ".join(body.split(". ", 1)[0].split())


def test_every_model_belongs_to_a_named_series():
    assert {_series_of(m) for m in MODEL_NAMES} == set(SERIES.values())


def test_the_first_sentence_names_every_series_and_the_count():
    sentence = _first_sentence()
    assert f"all {len(MODEL_NAMES)}" in sentence, sentence
    missing = [name for name in SERIES if not re.search(rf"\b{name}\b", sentence)]
    assert not missing, f"the first sentence omits the series {missing}: {sentence!r}"


def test_readme_names_only_models_that_exist_and_every_one():
    ids = set(re.findall(r"`((?:zu|c|pro|s|a)[0-9]+|minicobo)`", README))
    # in prose too: "Zu 5", "Pro 16", "A12"
    ids |= {f"{series.lower()}{number}" for series, number in
            re.findall(r"\b(Zu|C|Pro|S|A) ?([0-9]+)\b", README)}
    unknown = sorted(ids - set(MODEL_NAMES))
    assert not unknown, f"README names models that do not exist: {unknown}"
    missing = sorted(set(MODEL_NAMES) - ids)
    assert not missing, f"README omits the models {missing}"


def test_readme_is_short_enough_to_be_a_front_door():
    lines = README.count("\n")
    assert lines < MAX_LINES, f"README.md has {lines} lines; the detail belongs in docs/"


def test_package_xml_says_what_the_driver_serves():
    description = (ROOT / "package.xml").read_text().split("<description>")[1] \
        .split("</description>")[0]
    assert f"{len(MODEL_NAMES)}" in description
    missing = [name for name in SERIES if not re.search(rf"\b{name}\b", description)]
    assert not missing, f"package.xml's description omits {missing}"
