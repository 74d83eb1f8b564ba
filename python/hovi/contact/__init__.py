"""Rigid contact, what simulation and optimisation share: terrain (ground, gaps, boxes), point
contacts with Coulomb friction and flat feet with their contact wrench (force inputs of the model
for the trajectory optimiser; the integrator's contact stages in simulation). The complementarity
rows of contact-implicit optimisation and the reading of their sides live in ``hovi.trajopt``
(``complementarity``, ``contact_sides``). Nothing here imports hovi.trajopt."""
from .contacts import DEFAULT_FRICTION, ContactPoint, Contacts, friction_directions
from .flat_foot import FlatFoot, Stance, WrenchCone, flat_feet_contacts, wrench_cone
from .terrain import Box, Gap, Terrain

__all__ = ["Terrain", "Gap", "Box", "Contacts", "ContactPoint", "DEFAULT_FRICTION", "friction_directions", "FlatFoot",
           "flat_feet_contacts", "wrench_cone", "Stance", "WrenchCone"]
