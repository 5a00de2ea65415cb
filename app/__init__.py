"""Rigid Body Lab: the viser web app. Depends on :mod:`physics`; never the other way round."""
