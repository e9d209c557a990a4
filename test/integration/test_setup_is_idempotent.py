"""`make setup` run a second time checks, finds everything in place and changes nothing."""
import hashlib
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def tree_digest() -> str:
    """Digest of the files setup writes (devel/ and the venv's stamp)."""
    h = hashlib.sha256()
    for path in sorted((ROOT / "devel").rglob("*")) + [ROOT / ".venv" / "requirements.installed"]:
        if path.is_file():
            h.update(str(path).encode())
            h.update(str(path.stat().st_mtime_ns).encode())
            h.update(path.read_bytes())
    return h.hexdigest()


#: What each step of scripts/setup.sh says when it finds its part in place (a step that works
#: says something else: installing, creating, compiled, wrote)
IN_PLACE = ["Debian packages: all", ".venv: up to date", "messages: up to date",
            "IK library: up to date", "twin cycle library: up to date"]


def test_second_setup_is_quick_and_changes_nothing():
    """Quick because every step finds its part in place and does no work (a build or an
    install is what takes time): checked by what each step says it did, not by the wall clock,
    which the machine decides."""
    before = tree_digest()
    out = subprocess.run(["scripts/setup.sh"], cwd=ROOT, capture_output=True, text=True,
                         timeout=120)
    assert out.returncode == 0, out.stderr
    assert "installing" not in out.stdout and "creating" not in out.stdout, out.stdout
    said = out.stdout.splitlines()
    assert all(any(f"[setup] {step}" in line for line in said) for step in IN_PLACE), out.stdout
    assert not any(word in out.stdout for word in ("compiled", "wrote")), out.stdout
    assert tree_digest() == before
