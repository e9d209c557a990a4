"""`make setup` run a second time checks, finds everything in place and changes nothing."""
import hashlib
import subprocess
import time
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


def test_second_setup_is_quick_and_changes_nothing():
    before = tree_digest()
    t0 = time.monotonic()
    out = subprocess.run(["scripts/setup.sh"], cwd=ROOT, capture_output=True, text=True,
                         timeout=120)
    elapsed = time.monotonic() - t0
    assert out.returncode == 0, out.stderr
    assert "installing" not in out.stdout and "creating" not in out.stdout, out.stdout
    assert tree_digest() == before
    assert elapsed < 15.0, f"second setup took {elapsed:.1f} s"
