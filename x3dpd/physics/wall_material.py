"""Compliant walls: the contact constants of a sphere on an elastic wall (``WALLMAT`` card).

The report (Section 7.2.2) takes the cavity walls as rigid: a sphere of modulus E, Poisson's
ratio ν meets a flat wall with :math:`E^* = E/(1-\\nu^2)`. Its beam cavity is acrylic with
aluminium caps (Section 8), and the report names rigid walls among the likely causes of its
over-predicted damping. A ``WALLMAT`` record gives the walls of one CONTACT set (its triangles
and its CYLINDER / CAPSULE walls) an elastic material :math:`E_w, \\nu_w, \\mu_w`; a wall
contact then uses Hertz's mixed modulus (Johnson, *Contact Mechanics*, Eq. 4.22)

.. math::  \\frac{1}{E^*} = \\frac{1-\\nu_p^2}{E_p} + \\frac{1-\\nu_w^2}{E_w},

the wall's own radius of curvature being ignored as before (flat wall: :math:`R^* = R`).
In plane-strain moduli :math:`c = E/(1-\\nu^2)`: :math:`E^* = c_p c_w/(c_p + c_w)`, and a
rigid wall is :math:`c_w = \\infty` (:math:`E^* = c_p`).

Viscoelastic particles (report Eqs. 18-26): the wall is elastic, so it adds one long-term term
:math:`c_w` to the particle's terms :math:`c_{pk} = E_k/(1-\\nu_p^2)`, and every term is weighted
as a pair contact weights its bodies' terms (x3dpd.physics.maxwell): with the instantaneous
:math:`c_p = \\sum_k c_{pk}`, :math:`s = c_p c_w/(c_p + c_w)^2`, the wall-contact Hertz constants
are :math:`K_0 = \\tfrac43\\sqrt R\\,s\\,(c_{p0} + c_w)` and :math:`K_k = \\tfrac43\\sqrt
R\\,s\\,c_{pk}`.
The instantaneous response :math:`\\sum_k K_k = \\tfrac43\\sqrt R\\,E^*` is exact; the long-term
modulus is the same approximation as for two dissimilar particles.

Friction: the wall's :math:`\\mu_w` is the wall contact's friction coefficient (it replaces the
particle's PCOF on that wall; pair contacts keep the mean of the two PCOFs). A wall material
describes the pair of surfaces in contact, so one number per wall set is all a deck can
measure (e.g. a tilting test of the sphere on the wall).

The step loop is unchanged: a particle meets only the walls of its own cavity (CONTACT slave
set), so the wall constants are per particle -- the ``kw`` array the rigid wall already used,
and the per-particle wall friction coefficient. Units: any consistent set (psi or Pa).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["plane_strain_modulus", "plane_strain_moduli", "mixed_modulus", "mixed_shear_modulus",
           "particle_walls", "wall_friction", "wall_hertz_constants"]


def plane_strain_modulus(e: float, nu: float) -> float:
    """c = E / (1 - nu^2) [pressure]; a rigid wall is ``math.inf``."""
    return e / (1.0 - nu * nu)


def mixed_modulus(c_particle: float, c_wall: float) -> float:
    """E* = c_p c_w / (c_p + c_w) of plane-strain moduli; ``c_wall = inf`` gives c_p [pressure]."""
    if math.isinf(c_wall):
        return c_particle
    return c_particle * c_wall / (c_particle + c_wall)


def mixed_shear_modulus(e_p: float, nu_p: float, e_w: float, nu_w: float) -> float:
    """Mindlin's G* of a sphere on a wall: 1/G* = (2 - nu_p)/G_p + (2 - nu_w)/G_w with
    G = E/(2(1 + nu)); ``e_w = inf`` (rigid) gives G_p/(2 - nu_p) [pressure]."""
    inv = (2.0 - nu_p) * 2.0 * (1.0 + nu_p) / e_p
    if not math.isinf(e_w):
        inv += (2.0 - nu_w) * 2.0 * (1.0 + nu_w) / e_w
    return 1.0 / inv


def particle_walls(particle_cavity, wall_material) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per particle, the walls it meets: (E_w, nu_w, mu_w), each (P,); E_w = inf is a rigid
    wall, mu_w = nan the particle's own PCOF (no WALLMAT record for its set).

    ``particle_cavity`` (P,) cavity index (-1: none); ``wall_material`` (C, 3) E, NU, MU per
    cavity (x3dpd.model.model.Model.wall_material) or None (every wall rigid).
    """
    pcav = np.asarray(particle_cavity, dtype=np.int64)
    out = np.tile([math.inf, 0.0, math.nan], (pcav.shape[0], 1))
    if wall_material is not None:
        mat = np.asarray(wall_material, dtype=np.float64).reshape(-1, 3)
        mine = pcav >= 0
        out[mine] = mat[pcav[mine]]
    return out[:, 0].copy(), out[:, 1].copy(), out[:, 2].copy()


def wall_friction(mu, mu_wall) -> np.ndarray:
    """The friction coefficient of each particle's wall contacts: the wall's ``mu_wall``
    where a WALLMAT record gives one, else the particle's own ``mu`` (P,)."""
    mu = np.asarray(mu, dtype=np.float64)
    return np.where(np.isnan(mu_wall), mu, mu_wall)


def plane_strain_moduli(e_wall, nu_wall) -> np.ndarray:
    """c_w = E_w/(1 - nu_w^2) per particle (inf: rigid) [pressure]."""
    e_wall = np.asarray(e_wall, dtype=np.float64)
    with np.errstate(invalid="ignore"):
        return np.where(np.isinf(e_wall), math.inf,
                        e_wall / (1.0 - np.asarray(nu_wall, dtype=np.float64) ** 2))


def wall_hertz_constants(kw, ep, radius, c_wall) -> np.ndarray:
    """The wall-contact Hertz constants (P, K) [force/length^1.5]: ``kw`` (the rigid wall's
    4/3 c_pk sqrt(R)) where ``c_wall`` is inf, else the mixed constants of the module
    docstring from ``ep`` (P, K) the particles' plane-strain moduli c_pk and ``radius``."""
    out = np.array(kw, dtype=np.float64, copy=True)
    soft = ~np.isinf(np.asarray(c_wall, dtype=np.float64))
    if not soft.any():
        return out
    ep_s = np.asarray(ep, dtype=np.float64)[soft]
    cw = np.asarray(c_wall, dtype=np.float64)[soft]
    cp = ep_s.sum(axis=1)
    s = cp * cw / (cp + cw) ** 2
    terms = ep_s.copy()
    terms[:, 0] += cw
    out[soft] = 4.0 / 3.0 * (s * np.sqrt(np.asarray(radius, dtype=np.float64)[soft]))[:, None] \
        * terms
    return out
