"""The one lazy loader (``origami_cad._lazy``): a stub's names, imported on first use."""

from __future__ import annotations

import subprocess
import sys

import pytest

from origami_cad._lazy import stub_names


def test_a_stub_gives_each_name_its_module_and_refuses_anything_else(tmp_path):
    stub = tmp_path / "__init__.pyi"
    stub.write_text('"""Doc."""\nfrom json import dumps, loads as read\nfrom math import pi\n')
    assert stub_names(stub) == {"dumps": "json", "read": "json", "pi": "math"}
    stub.write_text("from .model import Thing\n")
    with pytest.raises(ImportError, match="not an absolute import"):
        stub_names(stub)


@pytest.mark.parametrize("package", ["origami_cad", "origami_cad.fabrication", "origami_cad.viz"])
def test_a_lazy_package_imports_a_name_only_when_used(package):
    code = (
        "import importlib, sys\n"
        f"p = importlib.import_module({package!r})\n"
        "before = set(sys.modules)\n"
        "name = sorted(n for n in p.__all__ if n != '__version__')[0]\n"
        "value = getattr(p, name)\n"
        "print(len(set(sys.modules) - before) > 0, name in vars(p), name in dir(p))\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["True", "True", "True"]
