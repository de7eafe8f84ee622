"""The examples in the package's docstrings run and print what they show: every module of
the built package npend, one test each, fails when an example's output changes."""

import doctest
import importlib
import pkgutil

import pytest

import npend

MODULES = ["npend"] + [f"npend.{m.name}" for m in pkgutil.iter_modules(npend.__path__)]


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name, tmp_path, monkeypatch):
    # Examples that write files (an animation) write them into a scratch folder.
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("MPLCONFIGDIR", str(tmp_path / "matplotlib"))
    module = importlib.import_module(name)
    result = doctest.testmod(module, optionflags=doctest.ELLIPSIS, report=True)
    assert result.failed == 0, f"{result.failed} of {result.attempted} examples in {name} failed"


def test_the_analyses_have_examples():
    # Every wrapper has one, so an empty run would mean the docstrings were not found.
    for name in ("npend", "npend.analysis", "npend.results"):
        assert doctest.testmod(importlib.import_module(name)).attempted > 0, name


def test_a_changed_output_fails():
    # The check above must notice an example whose output differs.
    def example():
        """
        >>> print(npend.embed([0.0, 1.0, 2.0], 1, 2))
        [[1. 0.]
         [2. 1.]]
        >>> print(npend.embed([0.0, 1.0, 2.0], 1, 2)[0, 0] + 1)
        1.0
        """

    runner = doctest.DocTestRunner(verbose=False)
    for test in doctest.DocTestFinder().find(example, globs={"npend": npend}):
        runner.run(test, out=lambda text: None)
    assert runner.summarize(verbose=False) == (1, 2)
