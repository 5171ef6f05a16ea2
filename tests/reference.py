"""Slow, obviously-correct references for the validation tests (numpy and scipy only).

Nothing here imports x3dpd: every expected value the tests assert is computed from textbook
formulas, so a mistake in the solver cannot leak into its own reference.

* Hertz impact closed forms (:func:`hertz_time_factor`, :func:`hertz_impact`).
* The Lee & Radok viscoelastic impact as an ODE solved with scipy (:func:`maxwell_impact`).
* The damped, driven SDOF oscillator, steady state and full transient (:func:`sdof_response`).
* Brute-force neighbour pairs (:func:`brute_pairs`).
* Contact forces on every node for one configuration (:func:`contact_forces`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import quad, solve_ivp

# ---------------------------------------------------------------------------------------------
# Hertz
# ---------------------------------------------------------------------------------------------


def hertz_time_factor() -> float:
    """int_0^1 (1 - x^{5/2})^{-1/2} dx (time to maximum compression in units of a_max / v)."""
    value, err = quad(lambda x: (1.0 - x**2.5) ** -0.5, 0.0, 1.0, epsabs=1e-14, epsrel=1e-13)
    assert err < 1e-10
    return value


def hertz_k(e_star: float, r_star: float) -> float:
    """K = 4/3 E* sqrt(R*), F = K a^{3/2}."""
    return 4.0 / 3.0 * e_star * math.sqrt(r_star)


@dataclass(frozen=True)
class HertzImpact:
    a_max: float  # maximum approach [in]
    t_max: float  # time of maximum approach [s]
    f_max: float  # peak force [lbf]

    @property
    def contact_time(self) -> float:
        return 2.0 * self.t_max


def hertz_impact(m_eff: float, k: float, v: float) -> HertzImpact:
    """Head-on Hertz impact of effective mass m_eff at relative speed v (energy balance
    1/2 m v^2 = 2/5 K a^{5/2} and the quadrature for the time)."""
    a_max = (5.0 * m_eff * v * v / (4.0 * k)) ** 0.4
    t_max = a_max / v * hertz_time_factor()
    return HertzImpact(a_max, t_max, k * a_max**1.5)


def zero_crossing(t, y, falling: bool) -> float:
    """Linearly interpolated time of the last sign change of y (+ to - if falling)."""
    k = np.nonzero((y[:-1] > 0) & (y[1:] <= 0) if falling else (y[:-1] < 0) & (y[1:] >= 0))[0][-1]
    return t[k] + (t[k + 1] - t[k]) * y[k] / (y[k] - y[k + 1])


def refined_peak(y) -> float:
    """Maximum of samples refined by the parabola through the largest sample and its neighbours."""
    k = int(np.argmax(y))
    y0, y1, y2 = y[k - 1 : k + 2]
    return y1 + (y2 - y0) ** 2 / (8.0 * (2.0 * y1 - y0 - y2))


# ---------------------------------------------------------------------------------------------
# Lee & Radok viscoelastic impact on a rigid wall
# ---------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class MaxwellImpact:
    t_peak_force: float  # time of the peak force [s]
    peak_force: float  # [lbf]
    t_max_approach: float  # time of maximum approach [s]
    max_approach: float  # [in]
    t_force_zero: float  # first time the force returns to zero after the peak [s]
    contact_time: float  # time the approach returns to zero [s]
    rebound_speed: float  # separation speed when the approach returns to zero [in/s]
    solution: object  # callable t -> (a, da/dt, F1) on [0, contact_time] (piecewise)


def maxwell_impact(
    m: float, radius: float, nu: float, moduli, taus, v: float, rtol: float = 1e-12
) -> MaxwellImpact:
    """Sphere (mass m, radius R) hitting a rigid wall at speed v, Lee & Radok contact force.

    With g(a) = 4/3 sqrt(R)/(1-nu^2) a^{3/2} and the relaxation function
    Psi(t) = E_0 + sum_k E_k exp(-t/tau_k), the hereditary integral
    F(t) = int_0^t Psi(t-t') dg/dt' dt' equals E_0 g(a) + sum_k F_k with the exact ODEs
    dF_k/dt = E_k dg/dt - F_k / tau_k, F_k(0) = 0. The applied force is max(0, F) (the report's
    clamp; the internal variables F_k keep evolving while it is clamped), and
    m d^2a/dt^2 = -max(0,F).
    Solved with DOP853 in segments split exactly at the events (the force crossing zero, the peak
    force, the maximum approach, the approach returning to zero).
    """
    moduli = np.asarray(moduli, float)
    e0, ek = moduli[0], moduli[1:]
    taus = np.asarray(taus, float)[1:]  # taus[0] belongs to E0 (infinite)
    c = 4.0 / 3.0 * math.sqrt(radius) / (1.0 - nu * nu)

    def parts(y):
        a, va = y[0], y[1]
        ap = max(a, 0.0)
        dg = 2.0 * math.sqrt(radius) / (1.0 - nu * nu) * math.sqrt(ap) * va  # dg/dt
        total = e0 * c * ap**1.5 + float(np.sum(y[2:]))
        return ap, va, dg, total

    def rhs(clamped):
        def f(t, y):
            _, va, dg, total = parts(y)
            force = 0.0 if clamped else max(total, 0.0)
            return np.concatenate(([va, -force / m], ek * dg - y[2:] / taus))

        return f

    def force_zero(t, y):
        return parts(y)[3]

    def approach_zero(t, y):
        return y[0]

    def velocity_zero(t, y):
        return y[1]

    def force_rate(t, y):
        # dF/dt = E_0 dg/dt + sum_k (E_k dg/dt - F_k / tau_k)
        _, _, dg, _ = parts(y)
        return e0 * dg + float(np.sum(ek * dg - y[2:] / taus))

    for fn in (force_zero, approach_zero, velocity_zero, force_rate):
        fn.direction = -1.0
        fn.terminal = True

    t_scale = hertz_impact(m, 4.0 / 3.0 * e0 / (1 - nu * nu) * math.sqrt(radius), v).t_max
    y = np.concatenate(([0.0, v], np.zeros(ek.shape[0])))
    # absolute tolerances per component: approach, velocity, Maxwell forces
    a_scale = v * t_scale
    f_scale = m * v / t_scale
    atol = rtol * np.concatenate(([a_scale, v], np.full(ek.shape[0], f_scale)))
    t = 0.0
    clamped = False
    pieces = []
    marks = {}
    # Every event function starts at zero or moves away from it in the opposite direction of the
    # crossing it watches, so none fires at the start of its segment; the maximum approach and the
    # peak force happen once (they are dropped afterwards, so a restart exactly at their root
    # cannot fire them again).
    for _ in range(50):
        events = [approach_zero]
        if clamped:
            events.append(_rising(force_zero))
        else:
            events.append(force_zero)
            if "max_approach" not in marks:
                events.append(velocity_zero)
            if "peak_force" not in marks:
                events.append(force_rate)
        sol = solve_ivp(
            rhs(clamped),
            (t, t + 50.0 * t_scale),
            y,
            method="DOP853",
            rtol=rtol,
            atol=atol,
            events=events,
            dense_output=True,
        )
        pieces.append((t, sol.t[-1], sol.sol))
        fired = [k for k, te in enumerate(sol.t_events) if len(te)]
        assert fired, "the reference impact did not end"
        k = min(fired, key=lambda q: sol.t_events[q][0])
        t = float(sol.t_events[k][0])
        y = sol.y_events[k][0].copy()
        name = events[k].__name__
        if name == "approach_zero":
            y[0] = 0.0
            marks["end"] = (t, y)
            break
        if name == "force_zero":
            marks.setdefault("force_zero", (t, y))
            clamped = True
        elif name == "rising":
            clamped = False
        elif name == "velocity_zero":
            marks["max_approach"] = (t, y)
            # elastic contact: the force peaks exactly at the maximum approach (both roots at the
            # same time; whichever the integrator reports first, the other is that same point)
            if "peak_force" not in marks and force_rate(t, y) <= 1e-9 * f_scale / t_scale:
                marks["peak_force"] = (t, y)
        elif name == "force_rate":
            marks.setdefault("peak_force", (t, y))
    else:
        raise AssertionError("too many segments in the reference impact")

    def solution(tq):
        for t0, t1, s in pieces:
            if t0 <= tq <= t1:
                return s(tq)
        raise ValueError(tq)

    tp, yp = marks["peak_force"]
    ta, ya = marks["max_approach"]
    tz, _ = marks.get("force_zero", marks["end"])
    te, ye = marks["end"]
    return MaxwellImpact(tp, parts(yp)[3], ta, float(ya[0]), tz, te, -float(ye[1]), solution)


def _rising(fn):
    def rising(t, y):
        return fn(t, y)

    rising.direction = 1.0
    rising.terminal = True
    return rising


# ---------------------------------------------------------------------------------------------
# SDOF oscillator
# ---------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Sdof:
    m: float
    k: float
    c: float
    force: float
    omega: float

    @property
    def wn(self) -> float:
        return math.sqrt(self.k / self.m)

    @property
    def zeta(self) -> float:
        return self.c / (2.0 * math.sqrt(self.k * self.m))

    @property
    def wd(self) -> float:
        return self.wn * math.sqrt(1.0 - self.zeta**2)

    @property
    def amplitude(self) -> float:
        """X = F / sqrt((k - m w^2)^2 + (c w)^2)."""
        return self.force / math.hypot(self.k - self.m * self.omega**2, self.c * self.omega)

    @property
    def phase(self) -> float:
        """Lag phi of x_p = X sin(w t - phi)."""
        return math.atan2(self.c * self.omega, self.k - self.m * self.omega**2)

    def decay_time(self, ratio: float) -> float:
        """Time for the homogeneous part exp(-zeta wn t) to fall by ``ratio``."""
        return math.log(1.0 / ratio) / (self.zeta * self.wn)

    def response(self, t, x0: float = 0.0, v0: float = 0.0) -> np.ndarray:
        """Exact x(t) of m x'' + c x' + k x = F sin(w t) from x(0) = x0, x'(0) = v0."""
        t = np.asarray(t, float)
        X, phi, w = self.amplitude, self.phase, self.omega
        xp = X * np.sin(w * t - phi)
        a = x0 - X * math.sin(-phi)
        b = (v0 - X * w * math.cos(-phi) + self.zeta * self.wn * a) / self.wd
        xh = np.exp(-self.zeta * self.wn * t) * (a * np.cos(self.wd * t) + b * np.sin(self.wd * t))
        return xp + xh

    def transient_amplitude(self, x0: float = 0.0, v0: float = 0.0) -> float:
        """Initial amplitude sqrt(A^2 + B^2) of the homogeneous part."""
        X, phi, w = self.amplitude, self.phase, self.omega
        a = x0 - X * math.sin(-phi)
        b = (v0 - X * w * math.cos(-phi) + self.zeta * self.wn * a) / self.wd
        return math.hypot(a, b)


# ---------------------------------------------------------------------------------------------
# Neighbour pairs
# ---------------------------------------------------------------------------------------------


def brute_pairs(x, radius, cavity=None, skin: float = 0.0, chunk: int = 512) -> np.ndarray:
    """All (i < j) in the same cavity with |x_i - x_j|^2 < (R_i + R_j + skin)^2, sorted.

    Distances use the same IEEE operations as a straightforward loop (dx*dx + dy*dy + dz*dz and
    (R_i + R_j) + skin) so that ties at the cut-off are decided identically.
    """
    x = np.asarray(x, float)
    n = x.shape[0]
    radius = np.broadcast_to(np.asarray(radius, float), (n,))
    cavity = np.zeros(n, np.int64) if cavity is None else np.asarray(cavity)
    out = []
    for s in range(0, n, chunk):
        i = np.arange(s, min(n, s + chunk))
        dx = x[None, :, 0] - x[i, None, 0]
        dy = x[None, :, 1] - x[i, None, 1]
        dz = x[None, :, 2] - x[i, None, 2]
        d2 = dx * dx + dy * dy + dz * dz
        cut = radius[i, None] + radius[None, :] + skin
        ok = (d2 < cut * cut) & (cavity[i, None] == cavity[None, :])
        ok &= np.arange(n)[None, :] > i[:, None]
        ii, jj = np.nonzero(ok)
        out.append(np.stack([i[ii], jj], axis=1))
    pairs = np.concatenate(out) if out else np.zeros((0, 2), np.int64)
    return pairs[np.lexsort((pairs[:, 1], pairs[:, 0]))].astype(np.int64)


# ---------------------------------------------------------------------------------------------
# Contact forces
# ---------------------------------------------------------------------------------------------


@dataclass
class Face:
    """A flat wall face: inward unit normal, a point on it and its triangles
    (node index triples)."""

    normal: np.ndarray
    point: np.ndarray
    triangles: list


def contact_forces(x, vel, *, p0, radius, mass, e, nu, mu, faces, gravity, dt, node_mass):
    """Force and moment (n, 6) on every node: gravity, Hertz normal and regularised Coulomb
    friction at every particle-wall and particle-particle contact (elastic, no history).

    ``x`` (n, 3), ``vel`` (n, 6) (translational, angular); particles are nodes ``p0..``; per
    particle ``radius``, ``mass``, ``e`` (Young's modulus), ``nu``, ``mu``. ``faces``: list of
    :class:`Face` (the walls every particle sees; wall nodes move with ``vel``). ``node_mass``
    (n,) for gravity. Returns (force, scale, info), where ``scale`` (n, 6) is the sum of the
    absolute values of all contributions (a yardstick for rounding) and ``info`` counts contacts
    and friction regimes.

    Physics (report 7.2): F_N = 4/3 E* sqrt(R*) a^{3/2} with 1/E* = sum (1-nu^2)/E, 1/R* = sum 1/R
    (a wall: R* = R, E* = E/(1-nu^2)); friction F_t = -min(m_t |v_t| / (2 dt), mu F_N) v_t/|v_t|
    with 1/m_t = sum over the particles in contact of (1/m + R^2/I), I = 2/5 m R^2, mu of a pair
    the mean of the two, v_t the tangential relative velocity of the contact points. A wall's
    reaction goes to its triangle's nodes with the barycentric weights of the contact point.
    """
    x = np.asarray(x, float)
    vel = np.asarray(vel, float)
    n = x.shape[0]
    npart = radius.shape[0]
    force = np.zeros((n, 6))
    scale = np.zeros((n, 6))
    info = {"wall": 0, "pair": 0, "stick": 0, "slip": 0}
    inertia = 0.4 * mass * radius**2
    inv_mt = 1.0 / mass + radius**2 / inertia

    def add(i, f, lo=0):
        force[i, lo : lo + 3] += f
        scale[i, lo : lo + 3] += np.abs(f)

    g = np.asarray(gravity, float)
    for i in range(n):
        if node_mass[i]:
            add(i, node_mass[i] * g)

    def friction(vt, fn, mu_c, m_t):
        s = np.linalg.norm(vt)
        if s == 0.0:
            return np.zeros(3)
        stick = 0.5 * m_t * s / dt
        slip = mu_c * fn
        info["stick" if stick < slip else "slip"] += 1
        return -min(stick, slip) * vt / s

    for p in range(npart):
        i = p0 + p
        r = radius[p]
        for face in faces:
            nrm = face.normal
            d = float(np.dot(x[i] - face.point, nrm))
            a = r - d
            if a <= 0.0:
                continue
            q = x[i] - d * nrm
            hit = None
            for tri in face.triangles:
                w = _barycentric(q, x[list(tri)])
                if np.all(w >= 0.0):
                    hit = (tri, w)
                    break
            if hit is None:
                continue
            tri, w = hit
            info["wall"] += 1
            fn = hertz_k(e[p] / (1.0 - nu[p] ** 2), r) * a**1.5
            rc = -r * nrm
            v_wall = sum(w[k] * vel[tri[k], :3] for k in range(3))
            vrel = vel[i, :3] + np.cross(vel[i, 3:], rc) - v_wall
            vt = vrel - np.dot(vrel, nrm) * nrm
            ft = friction(vt, fn, mu[p], 1.0 / inv_mt[p])
            f = fn * nrm + ft
            add(i, fn * nrm)
            add(i, ft)
            add(i, np.cross(rc, ft), 3)
            for k in range(3):
                add(tri[k], -w[k] * f)
    for p in range(npart):
        for q in range(p + 1, npart):
            i, j = p0 + p, p0 + q
            dvec = x[j] - x[i]
            dist = np.linalg.norm(dvec)
            a = radius[p] + radius[q] - dist
            if a <= 0.0:
                continue
            info["pair"] += 1
            nrm = dvec / dist
            e_star = 1.0 / ((1 - nu[p] ** 2) / e[p] + (1 - nu[q] ** 2) / e[q])
            r_star = radius[p] * radius[q] / (radius[p] + radius[q])
            fn = hertz_k(e_star, r_star) * a**1.5
            ci = vel[i, :3] + np.cross(vel[i, 3:], radius[p] * nrm)
            cj = vel[j, :3] + np.cross(vel[j, 3:], -radius[q] * nrm)
            vrel = cj - ci
            vt = vrel - np.dot(vrel, nrm) * nrm
            ft = friction(vt, fn, 0.5 * (mu[p] + mu[q]), 1.0 / (inv_mt[p] + inv_mt[q]))
            add(j, fn * nrm)
            add(j, ft)
            add(i, -fn * nrm)
            add(i, -ft)
            add(j, np.cross(-radius[q] * nrm, ft), 3)
            add(i, np.cross(radius[p] * nrm, -ft), 3)
    return force, scale, info


def _barycentric(q, corners):
    """Barycentric coordinates of q (in the triangle's plane) w.r.t. corners (3, 3)."""
    a, b, c = corners
    n = np.cross(b - a, c - a)
    area = np.dot(n, n)
    return (
        np.array(
            [
                np.dot(np.cross(c - b, q - b), n),
                np.dot(np.cross(a - c, q - c), n),
                np.dot(np.cross(b - a, q - a), n),
            ]
        )
        / area
    )


def box_faces(corners) -> list:
    """The six faces of a box given its 8 corners in the factories' cube order, inward normals."""
    corners = np.asarray(corners, float)
    centre = corners.mean(axis=0)
    tris = (
        (1, 2, 3),
        (1, 3, 4),
        (5, 7, 6),
        (5, 8, 7),
        (1, 6, 2),
        (1, 5, 6),
        (4, 3, 7),
        (4, 7, 8),
        (1, 4, 8),
        (1, 8, 5),
        (2, 6, 7),
        (2, 7, 3),
    )
    faces = []
    for k in range(0, 12, 2):
        t0 = [v - 1 for v in tris[k]]
        t1 = [v - 1 for v in tris[k + 1]]
        p = corners[t0]
        nrm = np.cross(p[1] - p[0], p[2] - p[0])
        nrm /= np.linalg.norm(nrm)
        if np.dot(centre - p[0], nrm) < 0:
            nrm = -nrm
        faces.append(Face(nrm, p[0].copy(), [tuple(t0), tuple(t1)]))
    return faces
