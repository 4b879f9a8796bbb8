"""Time-step policies of a run: the scene and the start of each step, chosen by the driver
(:class:`~pfem_skfem.drivers.resumable.ResumableRun`'s ``time_step``).

A policy answers two calls around every step and keeps what it needs between them as
plain values, saved in the run's checkpoint so that a resumed run takes the same steps:

- ``before(scene, state)`` returns (scene, state) of the next step: the run's scene with
  the step's dt, and the state it starts from;
- ``after(scene, state)`` is told the scene the step ran and the state it reached;
- ``saved()`` (a dict of plain values) and ``restore(saved)`` carry its memory through a
  checkpoint.

Without a policy a run takes its scene's dt at every step.
"""
from dataclasses import replace

import numpy as np

__all__ = ["AdaptiveTimeStep", "SofteningTimeStep"]


class AdaptiveTimeStep:
    """A time step chosen after each step from how far the fastest particle moved.

    The next step moves the fastest particle ``move`` spacings: dt grows by the ratio
    ``move spacing / (|v|max dt)`` (its square root when ``quasi_static``, where every
    step starts from rest and the displacement grows as dt^2), at most by ``growth``,
    and stays within [dt0, dt_max]. The steps taken are the rungs dt0 ladder^n at or
    below that dt, one scene per rung, made once from the run's scene (its theta-method
    with the rung's dt), so that a rung's problems are the same objects each time.

    Parameters
    ----------
    dt0, dt_max : the least and the largest time step (dt0: the run's scene's dt).
    move : spacings the fastest particle moves in a step (a Courant number).
    spacing : the particle spacing.
    quasi_static : every step starts from rest (velocities set to zero before it).
    ladder : the ratio of two rungs (> 1).
    growth : the largest ratio of two successive steps.
    """

    def __init__(self, dt0, dt_max, *, move, spacing, quasi_static=False, ladder=2 ** 0.25,
                 growth=1.5):
        if not dt0 > 0 or not ladder > 1:
            raise ValueError(f"dt0 must be > 0 and ladder > 1, got {dt0!r}, {ladder!r}")
        self.dt0, self.dt_max = float(dt0), float(max(dt_max, dt0))
        self.move, self.spacing = float(move), float(spacing)
        self.quasi_static, self.ladder, self.growth = bool(quasi_static), ladder, growth
        self.dt = self.dt0                   # the next step's dt before its rung is taken
        self._rungs = {}                     # rung n -> scene (rung 0: the run's scene)

    def scene(self, scene, dt):
        """The run's ``scene`` on the rung of ``dt``: dt0 ladder^n, n = floor(log_ladder
        (dt / dt0))."""
        n = int(np.floor(np.log(dt / self.dt0) / np.log(self.ladder) + 1e-9))
        if n not in self._rungs:
            if n == 0:
                self._rungs[0] = scene
            else:
                theta = replace(scene.config.theta, dt=self.dt0 * self.ladder ** n)
                self._rungs[n] = replace(scene, config=replace(scene.config, theta=theta))
        return self._rungs[n]

    def before(self, scene, state):
        """The scene of the next step (its rung) and the state it starts from (at rest
        when ``quasi_static``)."""
        if self.quasi_static:
            state = replace(state, v=np.zeros_like(state.v),
                            v_dofs=None if state.v_dofs is None else np.zeros_like(state.v_dofs))
        return self.scene(scene, self.dt), state

    def after(self, scene, state):
        """The next dt from the step just taken (``scene``'s dt) and its end ``state``."""
        speed = float(np.linalg.norm(state.v, axis=1).max()) if state.n else 0.0
        dt = scene.config.dt
        moved = max(speed * dt, 1e-300)                  # the fastest particle's move
        grow = self.move * self.spacing / moved
        grow = np.sqrt(grow) if self.quasi_static else grow
        self.dt = float(np.clip(min(grow, self.growth) * dt, self.dt0, self.dt_max))

    def saved(self):
        return {"dt": self.dt}

    def restore(self, saved):
        self.dt = float(saved["dt"])


class SofteningTimeStep:
    """The step control of a softening material (:mod:`pfem_skfem.pfem.softening`): a cap on
    the strength drop of a step.

    The step record's ``softening_drop`` is the largest drop of the step's strength update,
    as a fraction of c_p - c_r (:func:`~pfem_skfem.materials.softening.strength_drop`): c
    before minus c after for the exponential law, so that debris already near c_r, which
    that law never reaches, no longer halves dt; abs(H) Delta gamma^p at the points above
    c_r for the linear law (exact but where a point reaches c_r within the step). After a
    step above ``max_drop`` the next dt is half the last, after one below ``max_drop / 4``
    twice it, within [dt0 / 2^halvings, dt0]. The step over the cap is kept: gamma^p is
    updated after each step, and its control acts on the next one.
    The steps taken are the rungs dt0 / 2^n, one scene per rung, made once from the run's
    scene, so that a rung's problems are the same objects each time.

    Parameters
    ----------
    dt0 : the largest time step (the run's scene's dt).
    max_drop : the cap, a fraction of c_p - c_r in (0, 1].
    halvings : the most halvings of dt0 (a positive integer).
    """

    def __init__(self, dt0, *, max_drop=0.1, halvings=6):
        if not np.isfinite(dt0) or not dt0 > 0:
            raise ValueError(f"dt0 must be positive and finite, got {dt0!r}")
        if not np.isfinite(max_drop) or not 0 < max_drop <= 1:
            raise ValueError(f"max_drop (cap on the strength drop per step, a fraction of "
                             f"c_p - c_r) must lie in (0, 1], got {max_drop!r}")
        if int(halvings) != halvings or halvings < 1:
            raise ValueError(f"halvings must be a positive integer, got {halvings!r}")
        self.dt0, self.max_drop, self.halvings = float(dt0), float(max_drop), int(halvings)
        self.rung = 0                        # the next step's dt is dt0 / 2^rung
        self._rungs = {}

    def scene(self, scene, rung):
        """The run's ``scene`` with dt0 / 2^rung."""
        if rung not in self._rungs:
            theta = replace(scene.config.theta, dt=self.dt0 / 2 ** rung)
            self._rungs[rung] = (scene if rung == 0 else
                                 replace(scene, config=replace(scene.config, theta=theta)))
        return self._rungs[rung]

    def before(self, scene, state):
        """The scene of the next step (its rung) and the state it starts from."""
        return self.scene(scene, self.rung), state

    def after(self, scene, state):
        """The next rung from the step's ``softening_drop`` (none recorded: unchanged)."""
        drops = state.history.get("softening_drop")
        if not drops:
            return
        if drops[-1] > self.max_drop:
            self.rung = min(self.rung + 1, self.halvings)
        elif drops[-1] < self.max_drop / 4:
            self.rung = max(self.rung - 1, 0)

    def halved_after_cap(self, drops, dts):
        """Whether the control acted as stated over a run: after each step whose recorded
        drop (``drops``, the run's ``softening_drop``) exceeds the cap, the next step's dt
        (``dts``, each step's) is half the last, or the floor dt0 / 2^halvings."""
        drops, dts = np.asarray(drops, dtype=float), np.asarray(dts, dtype=float)
        over = np.flatnonzero(drops[:-1] > self.max_drop)
        floor = self.dt0 / 2 ** self.halvings
        return bool(np.all(np.isclose(dts[over + 1], np.maximum(dts[over] / 2, floor),
                                      rtol=1e-12)))

    def saved(self):
        return {"rung": self.rung}

    def restore(self, saved):
        self.rung = int(saved["rung"])
