"""Rigid contact for contact-implicit trajectory optimisation: terrain (ground, gaps, boxes), point
contacts with Coulomb friction and flat feet with their contact wrench, as force inputs of the
model (``hovi.trajopt.solve_contact`` solves the complementarity conditions without a mode
schedule)."""
from .contacts import ContactPoint, Contacts, friction_directions
from .flat_foot import FlatFoot, wrench_cone
from .terrain import Box, Gap, Terrain

__all__ = ["Terrain", "Gap", "Box", "Contacts", "ContactPoint", "friction_directions", "FlatFoot", "wrench_cone"]
