"""Public access to the catalogue of named mechanisms (see :mod:`symkin.model.catalogue`)."""
from symkin.model.catalogue import data, get, names

__all__ = ["data", "get", "names"]
