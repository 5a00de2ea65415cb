"""The lectures shipped with Rigid Body Lab: TOML files of steps for ``rigid-body-lab --lecture NAME``.

This folder is a package only so that its ``*.toml`` files are installed with the app (package data in
``pyproject.toml``) and found the same way from a source tree, an editable install or a wheel
(:data:`app.lectures.LECTURES`). It has no code; the format is described in :mod:`app.lectures`.
"""
