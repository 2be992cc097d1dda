"""Shared by the parity tests that read the training package."""
import importlib
import os
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


@pytest.fixture()
def train_import(monkeypatch):
    """importlib.import_module for deeprep_train modules, read fresh from
    this checkout's train/ (earlier imports dropped, sys.path restored after
    the test)."""
    monkeypatch.syspath_prepend(os.path.join(ROOT, "train"))
    for m in [m for m in sys.modules if m.startswith("deeprep_train")]:
        monkeypatch.delitem(sys.modules, m)
    return importlib.import_module
