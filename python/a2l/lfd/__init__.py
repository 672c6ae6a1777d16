"""Learning from demonstration: demonstrations and the diffeomorphic DS (thesis chapter 6).

``from a2l.lfd import DiffeoDS, Demonstration``; the fit is :mod:`a2l.lfd.fit`, the numpy
reference evaluation :mod:`a2l.lfd.reference`.
"""

from a2l.lfd.demonstration import Demonstration, load_demonstrations, save_demonstrations
from a2l.lfd.ds import DiffeoDS

__all__ = ["Demonstration", "DiffeoDS", "load_demonstrations", "save_demonstrations"]
