"""The build step pyproject.toml cannot say: the message catalogs compiled as the package is built.

``pip install`` (and a wheel) then carries ``app/language/locale/<lang>/LC_MESSAGES/rigid_body_lab.mo``
beside each ``.po`` (docs/translating.md); everything else about the package is in pyproject.toml.
"""

from __future__ import annotations

from pathlib import Path

from babel.messages.mofile import write_mo
from babel.messages.pofile import read_po
from setuptools import setup
from setuptools.command.build_py import build_py


def compile_catalogs(locale_dir: Path) -> list[Path]:
    """Every ``<lang>/LC_MESSAGES/*.po`` under ``locale_dir`` compiled to its ``.mo``; the ``.mo`` paths."""
    written = []
    for po in sorted(locale_dir.glob("*/LC_MESSAGES/*.po")):
        with po.open("rb") as source:
            catalog = read_po(source)
        with po.with_suffix(".mo").open("wb") as target:
            write_mo(target, catalog, use_fuzzy=False)
        written.append(po.with_suffix(".mo"))
    return written


class BuildWithCatalogs(build_py):
    """``build_py``, then the built package's catalogs compiled."""

    def run(self) -> None:
        super().run()
        compile_catalogs(Path(self.build_lib, "app", "language", "locale"))


if __name__ == "__main__":  # as setuptools runs it; a test imports compile_catalogs alone
    setup(cmdclass={"build_py": BuildWithCatalogs})
