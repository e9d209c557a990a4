"""The repository stands alone: what the code and the documents cite is in the clone.

* No file of the project cites a path outside the repository (a team workshop, an absolute
  path on somebody's machine, ``../`` above the root) or an issue number — a user with only a
  clone could follow neither.
* Every ``docs/<name>.md`` the code, README, scripts, tests or the documents cite exists.
* Every service, topic, parameter and action name the node uses (``src/jaka_driver/ros/``)
  appears in docs/interface.md, so the reference cannot fall behind the node.

Static reads of the files; nothing is imported or started.
"""
from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"
ROS = ROOT / "src" / "jaka_driver" / "ros"
THIS = Path(__file__).resolve()

# Citations a clone cannot follow. Case-insensitive; each with what it catches.
FORBIDDEN = [
    (r"\.\./shared\b|\bshared/(?:spec|notes)\b", "the team's shared folder"),
    (r"(?<![\w.])/work/", "an absolute path on the build machine"),
    (r"\bcontract\.md\b|\bjaka_facts\b|\bprotocol_evidence\b|\bplatform\.md\b",
     "a team spec file"),
    (r"\bissues?\s*#?\d+", "an issue number"),
    (r"\b(?:doc|facts)\s*§", "a section of a document outside the repository"),
]
FORBIDDEN_RE = [(re.compile(p, re.IGNORECASE), why) for p, why in FORBIDDEN]
PARENT_PATH = re.compile(r"(?<![\w.])(?:\.\./)+[\w.-]+(?:/[\w.-]+)*")   # not ".../x"

# The protocol engineer's directories: their sweep lands separately (docs/protocol.md).
PROTOCOL_SIDE = ("src/jaka_driver/protocol", "src/jaka_driver/controller",
                 "src/jaka_driver/emulator")
AREAS = ["README.md", "docs", "scripts", "launch", "config", "bench", "test",
         "src (outside protocol, controller, emulator)", *PROTOCOL_SIDE]


def _text_files(path: Path):
    paths = [path] if path.is_file() else sorted(p for p in path.rglob("*") if p.is_file())
    for p in paths:
        if p.resolve() == THIS or "__pycache__" in p.parts or "results" in p.relative_to(
                ROOT).parts[:2]:
            continue
        try:
            yield p, p.read_text(encoding="utf-8")
        except (UnicodeDecodeError, OSError):
            continue            # pictures, compiled files


def _area_files(area: str):
    if area.startswith("src "):
        for p, text in _text_files(ROOT / "src"):
            rel = p.relative_to(ROOT).as_posix()
            if not rel.startswith(PROTOCOL_SIDE):
                yield p, text
    else:
        yield from _text_files(ROOT / area)


def _outside_citations(path: Path, text: str) -> list[str]:
    found = []
    for n, line in enumerate(text.splitlines(), 1):
        where = f"{path.relative_to(ROOT)}:{n}"
        for pattern, why in FORBIDDEN_RE:
            m = pattern.search(line)
            if m:
                found.append(f"{where}: {why}: {m.group(0)!r}")
        for m in PARENT_PATH.finditer(line):
            target = (path.parent / m.group(0)).resolve()
            if ROOT not in target.parents and target != ROOT:
                found.append(f"{where}: a path above the repository: {m.group(0)!r}")
    return found


@pytest.mark.parametrize("area", AREAS)
def test_nothing_cites_a_path_outside_the_repository_or_an_issue(area):
    files = list(_area_files(area))
    assert files, f"no files found under {area}"
    offenders = [c for p, text in files for c in _outside_citations(p, text)]
    assert not offenders, "cite docs/... instead:\n" + "\n".join(offenders)


# ---- cited documents exist ----------------------------------------------------------------------

DOC_CITATION = re.compile(r"\bdocs/([\w-]+\.md)\b")
RELATIVE_DOC_LINK = re.compile(r"\]\(([\w-]+\.md)(?:#[\w-]*)?\)")


def _cited_docs() -> dict[str, list[str]]:
    """docs/<name>.md → where it is cited (code, README, scripts, tests, the documents)."""
    cited: dict[str, list[str]] = {}
    for top in ("README.md", "src", "scripts", "launch", "config", "bench", "test", "docs"):
        for p, text in _text_files(ROOT / top):
            names = set(DOC_CITATION.findall(text))
            if p.parent == DOCS:
                names |= set(RELATIVE_DOC_LINK.findall(text))
            for name in names:
                cited.setdefault(name, []).append(p.relative_to(ROOT).as_posix())
    return cited


CITED = _cited_docs()


def test_the_documents_are_cited():
    assert {"interface.md", "design.md", "models.md", "protocol.md"} <= set(CITED), sorted(CITED)


@pytest.mark.parametrize("name", sorted(CITED))
def test_every_cited_document_exists(name):
    assert (DOCS / name).is_file(), f"docs/{name} is cited by {CITED[name]} but does not exist"


def _slug(heading: str) -> str:
    """GitHub's anchor of a markdown heading."""
    return re.sub(r"[^\w\- ]", "", heading.strip().lower()).replace(" ", "-")


LINK = re.compile(r"\]\(([\w./-]*\.md)?#([\w-]+)\)")


@pytest.mark.parametrize("page", ["README.md", *sorted(p.name for p in DOCS.glob("*.md"))])
def test_links_to_sections_find_their_heading(page):
    path = ROOT / page if page == "README.md" else DOCS / page
    broken = []
    for target, anchor in LINK.findall(path.read_text(encoding="utf-8")):
        linked = (path.parent / target) if target else path
        if not linked.is_file():
            continue                    # a missing page is test_every_cited_document_exists'
        headings = re.findall(r"^#+ (.+)$", linked.read_text(encoding="utf-8"), re.MULTILINE)
        if anchor not in {_slug(h) for h in headings}:
            broken.append(f"{target or page}#{anchor}")
    assert not broken, f"{page} links to sections that do not exist: {broken}"


# ---- the node's names are documented -------------------------------------------------------------

PRIVATE_NAME = re.compile(r"^~[a-z_][a-z0-9_/]*$")


def _is_call_to(node: ast.AST, *names: str) -> bool:
    return (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute)
            and node.func.attr in names)


def node_names() -> set[str]:
    """Every name the ROS layer advertises or reads: services, topics, parameters, the action.

    * string arguments of ``rospy.Service`` / ``rospy.Publisher``;
    * where a service name is built (``f"~{name}"``), the table rows ``("name", SrvType, ...)``
      of that module;
    * every ``"~name"`` string (parameters, the action's default name).
    """
    names: set[str] = set()
    for path in sorted(ROS.glob("*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        built = False
        for node in ast.walk(tree):
            if _is_call_to(node, "Service", "Publisher") and node.args:
                first = node.args[0]
                if isinstance(first, ast.Constant) and isinstance(first.value, str):
                    names.add(first.value)
                elif isinstance(first, ast.JoinedStr):
                    built = True
            if (isinstance(node, ast.Constant) and isinstance(node.value, str)
                    and PRIVATE_NAME.match(node.value)):
                names.add(node.value)
        if built:
            for node in ast.walk(tree):
                if (isinstance(node, ast.Tuple) and len(node.elts) >= 3
                        and isinstance(node.elts[0], ast.Constant)
                        and isinstance(node.elts[0].value, str)
                        and isinstance(node.elts[1], (ast.Attribute, ast.Name))):
                    names.add(node.elts[0].value)
    return {n.lstrip("~/") for n in names}


NODE_NAMES = sorted(node_names())


def test_the_node_names_are_found():
    # A refactor that hides the names from this reader must not make the next test vacuous.
    for expected in ("joint_move", "clear_error", "get_ik", "sim/set_input", "sim/snapshot",
                     "tool_position", "joint_states", "diagnostics", "follow_joint_trajectory",
                     "jog_timeout"):
        assert expected in NODE_NAMES, f"{expected} not found in {ROS}: {NODE_NAMES}"
    assert len(NODE_NAMES) >= 40, NODE_NAMES


@pytest.mark.parametrize("name", NODE_NAMES)
def test_every_node_name_is_in_the_interface_document(name):
    text = (DOCS / "interface.md").read_text(encoding="utf-8")
    written = re.compile(r"`[~/]?(?:jaka_driver/)?" + re.escape(name) + r"`")
    assert written.search(text), f"`{name}` (src/jaka_driver/ros/) is not in docs/interface.md"
