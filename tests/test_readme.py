"""The README's and the user guide's Python examples run as written (from the repository root), and every link in
them resolves."""
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
BLOCKS = [(page, block) for page in PAGES for block in re.findall(r"```python\n(.*?)```", page.read_text(), re.S)]
LINKS = [(page, target) for page in PAGES for target in re.findall(r"\]\(([^)#]+)(?:#[^)]*)?\)", page.read_text())
         if not target.startswith(("http://", "https://"))]


@pytest.mark.parametrize("page, block", BLOCKS, ids=[f"{p.name}-{i}" for i, (p, _) in enumerate(BLOCKS)])
def test_example_runs(page, block, monkeypatch):
    monkeypatch.chdir(ROOT)
    exec(compile(block, f"{page.name} example", "exec"), {})


@pytest.mark.parametrize("page, target", LINKS, ids=[f"{p.name}:{t}" for p, t in LINKS])
def test_link_resolves(page, target):
    assert (page.parent / target).exists(), f"{page.name} links to {target}, which does not exist"


def test_readme_stays_a_guide():
    assert len((ROOT / "README.md").read_text()) <= 16_000
