"""Time MuJoCo's flex cloth on sprung's light stiff cloth (issue 35; `sprung
bench --goals`, bench/stiff_cloth.rs `light_cloth`) at the frame step, so
sprung's `projective` and `implicit_euler` can be set beside it.

The cloth, as sprung builds it: N x N particles, 1 m square, 0.2 kg in all
(0.2/N² kg each), springs of 2e4 N/m damped 0.5 N s/m (structural, shear
and bending: every spring the same), flat and level at height 0, pinned at
the two ends of one edge (sprung's particles N(N-1) and N²-1), falling and
swinging down under 9.81 m/s², dt = 1/60 s, nothing to collide with.

MuJoCo's model of it (MuJoCo is z-up: the cloth lies in the x-y plane,
gravity along -z):

- `<flexcomp type="grid" dim="2" count="N N 1" spacing="h h h">`, h =
  1/(N-1), `mass="0.2"`: one body of 0.2/N² kg per point, three slide joints
  each (pinned points: no joints). The grid is cut into 2(N-1)² triangles;
  their edges (rows, columns, one diagonal per square) are MuJoCo's "edges".
- Pins: `<pin grid="0 N-1  N-1 N-1"/>`, the two ends of the edge y = max.
- Stiffness. MuJoCo has no 2D edge springs: `<edge stiffness>` is for 1D
  flexes only (a compile error in 2D), `<edge damping>` and edge stiffness
  are refused by the `discrete` integrator, and edge `equality` constraints
  are stiff constraints (solref), not N/m springs. Its cloth stiffness is
  `<elasticity elastic2d="stretch">`: a Saint Venant-Kirchhoff membrane on
  linear triangles, energy per area t [mu tr(e²) + lambda*/2 tr(e)²] (Green
  strain e, plane stress lambda* = E nu/(1-nu²), mu = E/(2(1+nu))). Only the
  product E t matters for stretch. The mapping: sprung's spring lattice, all
  springs k, has for a small uniform strain the energy per area
      W = k (3 e11² + 3 e22² + e11 e22 + 2 e12²)
  (of the 3k e11²: structural k/2, bending springs (2h long) 2k, the
  diagonals k/2), i.e.
  C11 = 6k, C12 = k, C66 = k, independent of N. It is not isotropic, so no
  E, nu matches all three; we match uniaxial stretch along the grid's axes
  (how a hung cloth is mostly loaded): nu = C12/C11 = 1/6 and
  E t = C11 - C12²/C11 = 35k/6 = 1.167e5 N/m, with t = 1 mm, E = 1.167e8 Pa.
  Shear then reads mu t = 2.5k against sprung's k (MuJoCo's cloth is 2.5
  times stiffer in shear), and sprung's bending springs, which have no
  linear bending stiffness on a flat cloth, have no counterpart: elastic2d
  is "stretch", no bending energy.
- Damping: `<elasticity damping=beta>` is Rayleigh damping, D = beta K; for
  one spring D = beta k u uᵀ, so beta = c/k = 0.5/2e4 = 2.5e-5 s gives each
  mode the damping the springs' 0.5 N s/m gives it (exact for a linearised
  spring; applied to the membrane's K here).
- Integrator: `discrete` (`--integrator NAME` to try another). In MuJoCo 4
  it is the only implicit-in-position one: it solves (M + hD + h²K) a = f
  - hKv, a linearised backward-Euler step like sprung's implicit ones (no
  constraints here, so the Newton solver does no iterations; the work is
  that smooth solve). `implicit` and `implicitfast` are implicit in velocity only; with
  flex elasticity MuJoCo 4.0.1 refuses them ("flex elasticity is no longer
  integrated implicitly under integrator='implicit' and 'implicitfast'"),
  and integrated explicitly this cloth would need dt ~ 1e-5 s. The figures
  the goals quote (issue 35) were taken with `discrete`. Its smooth solve
  is iterative (per-vertex 3x3 block preconditioner on M + h²K), its cap
  growing with `iterations` (default 100): at 128² it stops short of
  `tolerance` (residual ~6e-3) on nearly every step and the cloth falls
  too slowly (lowest point -0.32 m after 1 s, against -0.93 to -0.96 m at
  16² to 64²); the row's form then says in how many steps. `--iterations
  1000` reaches ~1e-5 at 5 to 10 times the cost.
- No contacts: `<flag contact="disable"/>`, and the flex's own contype,
  conaffinity 0, selfcollide "none".

Threads: `mju_threadpool(d, THREADS)` attaches a pool of THREADS workers to
the mjData (MuJoCo >= 3.10; without it the row reads "n/a (no
thread pool in this mujoco)"). The pool parallelises collision and the
constraint solve across islands; one cloth with no contacts is one island,
so expect little from it. THREADS = 1 attaches no pool.

Timing: each of 3 rounds resets the cloth to flat, takes 2 untimed steps,
then steps until at least 30 steps and 1 s have passed; the row gives the
median ms a step. The spring column is empty (MuJoCo has triangles, not
springs). `--check` also prints (to stderr) the lowest point's height and
the edges' strain after 1 s (60 steps) from flat.
Usage: python mujoco_cloth.py N [THREADS] [--check] [--integrator NAME]
       [--iterations K]"""

import statistics
import sys
import time

import numpy as np
import mujoco

K = 2e4  # N/m, each sprung spring
C = 0.5  # N s/m, each spring's damping
MASS = 0.2  # kg, the whole cloth
THICKNESS = 1e-3  # m; only E * thickness matters for stretch
FRAME = 1.0 / 60.0  # s


def model_xml(n, integrator):
    """The MJCF of the n x n cloth (see the docstring for the mapping)."""
    h = 1.0 / (n - 1)
    nu = 1.0 / 6.0  # C12 / C11 of sprung's lattice
    young = (35.0 / 6.0) * K / THICKNESS  # E t = C11 - C12²/C11
    return f"""
<mujoco model="sprung light stiff cloth {n}">
  <option timestep="{FRAME!r}" integrator="{integrator}" gravity="0 0 -9.81">
    <flag contact="disable"/>
  </option>
  <worldbody>
    <flexcomp name="cloth" type="grid" dim="2" count="{n} {n} 1"
              spacing="{h!r} {h!r} {h!r}" mass="{MASS}" radius="0.001">
      <elasticity young="{young!r}" poisson="{nu!r}" thickness="{THICKNESS}"
                  damping="{C / K!r}" elastic2d="stretch"/>
      <contact contype="0" conaffinity="0" selfcollide="none"/>
      <pin grid="0 {n - 1}  {n - 1} {n - 1}"/>
    </flexcomp>
  </worldbody>
</mujoco>"""


# MuJoCo's warnings, caught: by default it prints them and writes
# MUJOCO_LOG.TXT into the working directory.
WARNINGS = []
mujoco.set_mju_user_warning(WARNINGS.append)
UNCONVERGED = int(mujoco.mjtWarning.mjWARN_INERTIA)  # M+K solve short of tol.


def ms_per_step(m, d, rounds=3, steps=30, least=1.0):
    """Median over rounds of the ms a step, each round from flat, and the
    steps (of all taken) whose M+K solve stopped short of its tolerance."""
    figures, short, total = [], 0, 0
    for _ in range(rounds):
        mujoco.mj_resetData(m, d)
        for _ in range(2):  # untimed, as sprung's bench
            mujoco.mj_step(m, d)
        taken, start = 0, time.perf_counter()
        while taken < steps or time.perf_counter() - start < least:
            mujoco.mj_step(m, d)
            taken += 1
        figures.append((time.perf_counter() - start) / taken * 1e3)
        short += d.warning[UNCONVERGED].number
        total += taken + 2
        if not np.all(np.isfinite(d.qpos)):
            return None, short, total
    return statistics.median(figures), short, total


def check(m, d):
    """The lowest point and the edges' strain 1 s from flat."""
    mujoco.mj_resetData(m, d)
    for _ in range(round(1.0 / FRAME)):
        mujoco.mj_step(m, d)
    x = d.flexvert_xpos
    strain = d.flexedge_length / m.flexedge_length0 - 1.0
    pinned = np.flatnonzero(m.flex_vertbodyid == 0).tolist()
    print(f"# check n={m.flex_vertnum[0] ** 0.5:.0f}: after 1 s lowest z "
          f"{x[:, 2].min():.4f} m, pinned {pinned} at "
          f"{x[pinned].round(4).tolist()}, edge strain "
          f"{strain.min():.2e}..{strain.max():.2e}, finite "
          f"{bool(np.all(np.isfinite(x)))}, M+K solve short in "
          f"{d.warning[UNCONVERGED].number} of 60 steps", file=sys.stderr)


def main(argv):
    flags = {"--check": False, "--integrator": "discrete", "--iterations": None}
    numbers = []
    i = 0
    while i < len(argv):
        if argv[i] == "--check":
            flags["--check"] = True
        elif argv[i] in flags:  # --integrator NAME, --iterations K
            flags[argv[i]] = argv[i + 1]
            i += 1
        else:
            numbers.append(int(argv[i]))
        i += 1
    n = numbers[0] if numbers else 64
    threads = numbers[1] if len(numbers) > 1 else 1
    integrator = flags["--integrator"]
    row = f"mujoco,flex membrane ({integrator}),{n},{threads}"
    try:
        m = mujoco.MjModel.from_xml_string(model_xml(n, integrator))
        if flags["--iterations"]:
            m.opt.iterations = int(flags["--iterations"])
        d = mujoco.MjData(m)
        mujoco.mj_step(m, d)  # some settings are refused only at run time
    except ValueError as error:
        reason = str(error).splitlines()[-1].replace(",", ";")
        print(f"{row},n/a (mujoco {mujoco.__version__}: {reason}),")
        return 1
    if threads > 1:
        if not hasattr(mujoco, "mju_threadpool"):
            print(f"{row},n/a (no thread pool in this mujoco),")
            return 0
        mujoco.mju_threadpool(d, threads)
    ms, short, total = ms_per_step(m, d)
    if short:  # MuJoCo's step is then not the converged implicit step
        row = row.replace(")", f"; M+K solve short in {short}/{total} steps)")
    print(f"{row},{'blew up' if ms is None else f'{ms:.4f}'},")
    if flags["--check"]:
        check(m, d)
    if WARNINGS:
        print(f"# mujoco warned {len(WARNINGS)} times, first: {WARNINGS[0]}",
              file=sys.stderr)
    return 0 if ms is not None else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
