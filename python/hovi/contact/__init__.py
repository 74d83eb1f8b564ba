"""Rigid contact for contact-implicit trajectory optimisation: terrain (ground, gaps, boxes), point
contacts with Coulomb friction and flat feet with their contact wrench, as force inputs of the
model, and the complementarity rows of point contacts on a transcription's points with the
reading of their sides (``hovi.trajopt.solve_contact`` solves the conditions without a mode
schedule). Nothing here imports hovi.trajopt."""
from .complementarity import Branches, ComplementarityRelaxation, ContactRows
from .contacts import DEFAULT_FRICTION, ContactPoint, Contacts, friction_directions
from .flat_foot import FlatFoot, Stance, WrenchCone, flat_feet_contacts, wrench_cone
from .sides import branches_from, branches_of, canonical, least_slack, opposite_pairs
from .terrain import Box, Gap, Terrain

__all__ = ["Terrain", "Gap", "Box", "Contacts", "ContactPoint", "DEFAULT_FRICTION", "friction_directions", "FlatFoot", "flat_feet_contacts", "wrench_cone",
           "Stance", "WrenchCone", "ContactRows", "Branches", "ComplementarityRelaxation", "branches_of", "branches_from", "canonical",
           "least_slack", "opposite_pairs"]
