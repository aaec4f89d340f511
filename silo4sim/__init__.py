"""Physics replay of a plan in MuJoCo (docs/physics.md).

A layer beside ``viz``: reads a robot (silo4kin) and a trajectory or run folder
(planner.trajectory.samples, planner.outputs.export), never the planner's internals;
imports ``mujoco`` only inside its functions (optional extra ``silo4kin[sim]``).

Modules: ``urdf_collisions`` (URDF text -> collision shapes, inertia fix-up), ``settings``
(physics and servo settings, gains per robot), ``model`` (MjSpec: free base, floor, feet,
servos, sensors), ``replay`` (servo references, rollout),
``metrics`` (falls, drift, slip, contacts, torques, verdict), ``run`` (calibration, replay,
files), ``errors``.
"""
