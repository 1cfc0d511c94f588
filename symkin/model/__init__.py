"""Plain-data description of mechanisms (no sympy, CasADi or matplotlib here)."""
from symkin.model.mechanism import Mechanism, Parameter, Slider
from symkin.model.model_file import read_model, write_model
from symkin.model.validation import parse_mechanism

__all__ = ["Mechanism", "Parameter", "Slider", "read_model", "write_model", "parse_mechanism"]
