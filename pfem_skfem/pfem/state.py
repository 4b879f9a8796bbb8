"""The state of a PFEM run between steps, and its checkpoints (thesis Section 2.2).

A :class:`PFEMState` is the particle cloud C^n with everything the next step needs
from the last one (the mesh moved to t_n with its P2 velocities and stresses, the
lagged mean stress, the solver's scales) and the run's bookkeeping (material
discharged through outlets, the history of step records). A checkpoint stores it
exactly, so a resumed run is bit-identical to an uninterrupted one.
"""
from dataclasses import dataclass, field, replace
from typing import ClassVar
import json
import os
from pathlib import Path
import secrets

import numpy as np

from ..problems.step_scaling import DynamicScales
from .particles import Particles, check_positions


@dataclass(kw_only=True)
class PFEMState(Particles):
    """Everything that carries over from one step to the next (and into a checkpoint).

    A :class:`~pfem_skfem.pfem.Particles` cloud (x, h, v, and the tags free_surface:
    on the boundary of the last mesh or flying free, contact: pressed against a rigid
    body in the last step), validated the same way, and:

    Attributes
    ----------
    step, time : steps taken and time reached.
    sigma_m : (n,) lagged, smoothed mean stress (sx + sy)/2 carried by the particles.
    region : (n,) index of the material region of each particle (0 by default).
    mass : (n,) mass of each particle (per unit length in plane strain); it is only
        passed on, never created: particles added at the surface carry none, a thinned
        particle hands its mass to its nearest neighbour, and with
        ``PFEMConfig.spread_mass`` each region's mass is spread over its particles by
        their lumped areas at each remeshing, so the material inside plus the material
        discharged is the initial mass at every step.
    mesh_p, mesh_t : the current mesh (vertices moved to t_n); mesh_particle : particle
        of each vertex (-1: a particle dropped since).
    v_dofs : (n_u,) P2 velocities on it.  sigma : (n_points, 4) stresses at its stress points.
    scales : the previous step's :class:`~pfem_skfem.problems.step_scaling.DynamicScales`
        (None before the first step).
    area0 : area of the initial domain.  alpha : the current alpha.
    discharged : {outlet name: [mass, particle count]} that left through each outlet.
    history : {name: list}, one entry per step record (appended by the driver).
    stress0 : (n, 4) initial stresses (sx, sy, sz, sxy) at the particles, interpolated
        to the stress points of the first mesh (None: zero), which an elastoplastic
        body needs to start in equilibrium.
    pore_pressure : (n,) the pore pressure at the particles (None: a scene without water).
        It is continuous P1 on each step's mesh, whose vertices are particles: the
        particles carry it through remeshing (:mod:`pfem_skfem.scene.water`).
    gamma_p : (n_points,) accumulated plastic shear strain at the stress points of the
        mesh, beside ``sigma`` and carried as it is (mapped at each remeshing by the
        stresses' scheme, :func:`~pfem_skfem.pfem.softening.carried_strain`); None: zero
        everywhere, and not carried (a run without a softening material).

    A run whose every particle has left through the outlets ends with an empty state
    (n = 0): its history and discharged totals complete, nothing left to step.
    """

    may_be_empty: ClassVar[bool] = True

    step: int
    time: float
    sigma_m: np.ndarray
    region: np.ndarray = None
    mass: np.ndarray = None
    mesh_p: np.ndarray = None
    mesh_t: np.ndarray = None
    mesh_particle: np.ndarray = None
    v_dofs: np.ndarray = None
    sigma: np.ndarray = None
    scales: DynamicScales = None
    area0: float = np.nan
    alpha: float = np.nan
    discharged: dict = field(default_factory=dict)
    history: dict = field(default_factory=dict)
    stress0: np.ndarray = None
    pore_pressure: np.ndarray = None
    gamma_p: np.ndarray = None

    def __post_init__(self):
        super().__post_init__()
        self.sigma_m = np.asarray(self.sigma_m, dtype=float)
        if self.sigma_m.shape != (self.n,):
            raise ValueError(f"sigma_m must have shape ({self.n},), got {self.sigma_m.shape}")
        self.region = (np.zeros(self.n, dtype=int) if self.region is None
                       else np.asarray(self.region, dtype=int))
        if self.region.shape != (self.n,):
            raise ValueError(f"region must have shape ({self.n},), got {self.region.shape}")
        self.mass = (np.zeros(self.n) if self.mass is None
                     else np.asarray(self.mass, dtype=float))
        if self.mass.shape != (self.n,) or np.any(self.mass < 0):
            raise ValueError(f"mass must be ({self.n},) non-negative values")
        if self.stress0 is not None:
            self.stress0 = np.asarray(self.stress0, dtype=float)
            if self.stress0.shape != (self.n, 4):
                raise ValueError(f"stress must have shape ({self.n}, 4), got {self.stress0.shape}")
        if self.pore_pressure is not None:
            self.pore_pressure = np.asarray(self.pore_pressure, dtype=float)
            if self.pore_pressure.shape != (self.n,):
                raise ValueError(f"pore_pressure must have shape ({self.n},), got "
                                 f"{self.pore_pressure.shape}")
        if self.gamma_p is not None:
            self.gamma_p = np.asarray(self.gamma_p, dtype=float)
            if (self.gamma_p.ndim != 1 or not np.all(np.isfinite(self.gamma_p))
                    or np.any(self.gamma_p < 0)):
                raise ValueError("gamma_p (plastic shear strain at the stress points) must be "
                                 "a 1-d array of finite values >= 0")
            if self.sigma is not None and len(self.gamma_p) != len(self.sigma):
                raise ValueError(f"gamma_p must have one value per stress point of sigma "
                                 f"({len(self.sigma)}), got {len(self.gamma_p)}")

    def subset(self, keep):
        """The state restricted to the kept particles (boolean mask); the old mesh keeps
        its own vertex data, with -1 for a vertex whose particle was dropped."""
        keep = np.asarray(keep, dtype=bool)
        mesh_particle = self.mesh_particle
        if mesh_particle is not None:
            index = np.full(len(keep), -1)
            index[keep] = np.arange(int(keep.sum()))
            mesh_particle = index[mesh_particle]
        return replace(self, x=self.x[keep], v=self.v[keep], h=self.h[keep],
                       free_surface=self.free_surface[keep], contact=self.contact[keep],
                       sigma_m=self.sigma_m[keep], region=self.region[keep],
                       mass=self.mass[keep], mesh_particle=mesh_particle,
                       stress0=None if self.stress0 is None else self.stress0[keep],
                       pore_pressure=(None if self.pore_pressure is None
                                      else self.pore_pressure[keep]))

    def appended(self, x, v, h, sigma_m, region, mass=None, pore_pressure=None,
                 stress0=None):
        """The state with new particles (new arrays), e.g. nodes added by a remesher
        (``pore_pressure``, ``stress0``: theirs, where the state carries them; zero if
        not given)."""
        k = len(x)
        no = np.zeros(k, dtype=bool)
        if self.pore_pressure is not None:
            added = np.zeros(k) if pore_pressure is None else np.asarray(pore_pressure, float)
            pore_pressure = np.concatenate([self.pore_pressure, added])
        if self.stress0 is not None:
            stress0 = np.vstack([self.stress0, np.zeros((k, 4)) if stress0 is None
                                 else np.asarray(stress0, dtype=float)])
        return replace(self, pore_pressure=pore_pressure, stress0=stress0,
                       x=np.vstack([self.x, x]), v=np.vstack([self.v, v]),
                       h=np.concatenate([self.h, h]),
                       sigma_m=np.concatenate([self.sigma_m, sigma_m]),
                       region=np.concatenate([self.region, region]),
                       mass=np.concatenate([self.mass, np.zeros(k) if mass is None else mass]),
                       free_surface=np.concatenate([self.free_surface, no]),
                       contact=np.concatenate([self.contact, no]))

    @property
    def total_mass(self):
        """Mass of the particles of the cloud (inside the body, or flying free)."""
        return float(self.mass.sum())


def initial_state(x, h, sigma_m=None, stress=None, *, region=None, mass=None):
    """The state at t = 0: particles at rest with a lagged mean stress (zero by default)
    and, optionally, initial stresses (n, 4), region indices and masses per particle."""
    x = check_positions(x)                       # ValueError for an empty or bad cloud
    sm = np.zeros(len(x)) if sigma_m is None else sigma_m
    return PFEMState(step=0, time=0.0, x=x.copy(), h=np.array(h, dtype=float), sigma_m=sm,
                     stress0=stress, region=region, mass=mass)


# -- checkpoints -----------------------------------------------------------------------
_ARRAYS = ("x", "v", "h", "free_surface", "contact", "sigma_m", "region", "mass", "mesh_p",
           "mesh_t", "mesh_particle", "v_dofs", "sigma", "stress0", "pore_pressure",
           "gamma_p")


class CheckpointError(ValueError):
    """A checkpoint file that cannot be read: damaged, truncated, or not a checkpoint."""


def save_checkpoint(path, state, *, meta=None):
    """Write the state to ``path`` (np.savez_compressed, ".npz" added if missing).

    Arrays are stored exactly, the history as JSON text (which numpy stores at 4 bytes a
    character: it compresses well). The file is written under a temporary name unique
    to this writer and then renamed, so that a stop while writing leaves the previous
    checkpoint whole and two writers never share a temporary file.

    Parameters
    ----------
    path : the checkpoint file.
    state : the :class:`PFEMState`.
    meta : optional JSON-able dict stored with the state (e.g. the scene's digest and
        the step records of a run), read back by ``load_checkpoint(path, meta=True)``.
    """
    data = {k: getattr(state, k) for k in _ARRAYS if getattr(state, k) is not None}
    sc = state.scales
    scales = (np.full(3, np.nan) if sc is None
              else np.array([sc.stress, sc.displacement, sc.dynamic_force]))
    path = Path(path)
    path = path if path.suffix == ".npz" else path.with_name(path.name + ".npz")
    tmp = path.with_name(f"{path.stem}.{os.getpid()}.{secrets.token_hex(4)}.tmp.npz")
    extra = {} if meta is None else {"meta": json.dumps(meta)}
    try:
        np.savez_compressed(tmp, step=state.step, time=state.time, area0=state.area0,
                            alpha=state.alpha, scales=scales, history=json.dumps(state.history),
                            discharged=json.dumps(state.discharged), **extra, **data)
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)


def load_checkpoint(path, *, meta=False):
    """A state written by :func:`save_checkpoint`.

    Parameters
    ----------
    path : the checkpoint file.
    meta : also return the ``meta`` dict stored with it ({} if none).

    Returns
    -------
    PFEMState, or (PFEMState, dict) with ``meta``.

    Raises
    ------
    CheckpointError (a ValueError) naming the file when it is damaged or not a checkpoint.
    """
    try:
        with np.load(path, allow_pickle=False) as z:
            kw = {k: z[k].copy() for k in _ARRAYS if k in z.files}
            s = z["scales"]
            scales = DynamicScales(*map(float, s)) if np.all(np.isfinite(s)) else None
            discharged = json.loads(str(z["discharged"])) if "discharged" in z.files else {}
            info = json.loads(str(z["meta"])) if "meta" in z.files else {}
            state = PFEMState(step=int(z["step"]), time=float(z["time"]),
                              area0=float(z["area0"]), alpha=float(z["alpha"]), scales=scales,
                              discharged=discharged, history=json.loads(str(z["history"])), **kw)
    except FileNotFoundError:
        raise
    except Exception as err:        # BadZipFile, EOFError, zlib, KeyError, a pickle refusal
        why = type(err).__name__ if "pickle" in str(err) else f"{type(err).__name__}: {err}"
        raise CheckpointError(f"{path} is damaged or not a checkpoint ({why})") from None
    if state.step < 0:
        raise CheckpointError(f"{path} is damaged (step {state.step} < 0)")
    return (state, info) if meta else state
