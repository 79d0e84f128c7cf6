"""The paper's tip impact in Exudyn with 3D geometrically exact beams struck by a point mass.

Peer measurement for `cargo xtask simulate` (see README.md in this folder), the 3D counterpart of
exudyn_tip.py: the same scene, solver settings and output. Not part of the build, the tests or CI.
Usage, in a virtual environment outside the repository:

    pip install exudyn numpy
    python validation/peers/exudyn_tip3d.py --elements 256 --end-time 0.001 --step 1e-6
    python validation/peers/exudyn_tip3d.py --elements 256 --end-time 0.001 --step 1e-6 --offset 0.01

It prints the wall time of the solve (not of building the model) and the contacts found from the
gap between the ball and the struck point: start (us), duration (us) and peak force (N).

Model
-----
Beam along x, clamped at x = 0, free at x = L; width b along y, thickness t along z; the ball moves
along -z. ObjectBeamGeometricallyExact elements (two-node, SE(3)-interpolated, shear deformable)
on NodeRigidBodyRotVecLG nodes (rotation-vector Lie group nodes; the implicit generalized-alpha
solver treats them by its Lie group update). Section, in the element's local frame (x the axis):

    stiffness diag(EA, k G A, k G A, G J, E Iyy, E Izz), k = 5/6,
    Iyy = b t^3 / 12 (bending in z, the struck direction), Izz = t b^3 / 12,
    J = (b t^3 / 3)(1 - 0.630 t / b) (the Saint-Venant series gives a value 6e-5 lower),
    mass per length rho A, rotary inertia per length rho diag(Iyy + Izz, Iyy, Izz).

The element integrates its mass with two Lobatto points (translational and rotary mass lumped at
the nodes). Clamp: the six coordinates of node 0 (displacements and rotation vector) held at zero
by ObjectConnectorCoordinate to a ground node, as in the planar script.

Contact: ObjectContactSphereSphere between the ball (NodePoint + ObjectMassPoint) and a sphere of
radius t/2 centred on the beam axis at the struck point, Hertz stiffness 4/3 E* sqrt(R_ball),
exponent 1.5, no damping, no friction. For the centred strike (--offset 0, the default) that
sphere sits on the tip node (MarkerNodePosition), exactly as in exudyn_tip.py. With --offset e the
sphere is centred at the section point (x = L, y = e) of the last element (MarkerBodyPosition at
local position [L_e/2, e, 0]); that point follows the section's rotation, so the contact force
acts through it and applies the moment e x F to the beam: the strike twists the tip (checked
against a tip force plus the torque -e F_z about x). The ball starts at y = e.

Settings as in exudyn_tip.py: generalized-alpha (spectral radius 0.9) at fixed steps, Newton
relative tolerance 1e-6, one discontinuous iteration, Eigen's sparse solver, gravity off.
"""
import argparse
import time

import numpy as np
import exudyn as exu
from exudyn.itemInterface import (
    NodeRigidBodyRotVecLG, NodePoint, NodePointGround, NodeGenericData,
    ObjectBeamGeometricallyExact, ObjectMassPoint, ObjectContactSphereSphere, ObjectGround,
    MarkerNodeCoordinate, MarkerNodePosition, MarkerBodyPosition, ObjectConnectorCoordinate,
    SensorNode, SensorMarker)

# The scene of validation/scenes/paper-tip.toml, gravity off.
L, WIDTH, THICK = 1.15, 0.025, 0.005
E, NU, RHO = 2.1e11, 0.3, 7850.0
R_BALL, M_BALL = 0.005, 0.009
SPEED = (2 * 9.81 * 0.2) ** 0.5
SHEAR_FACTOR = 5.0 / 6.0


def section():
    area = WIDTH * THICK
    i_yy = WIDTH * THICK ** 3 / 12  # about y: bending in z, the struck direction
    i_zz = THICK * WIDTH ** 3 / 12
    torsion = WIDTH * THICK ** 3 / 3 * (1 - 0.630 * THICK / WIDTH)
    g = E / (2 * (1 + NU))
    sec = exu.BeamSection()
    sec.stiffnessMatrix = np.diag([E * area, SHEAR_FACTOR * g * area, SHEAR_FACTOR * g * area,
                                   g * torsion, E * i_yy, E * i_zz])
    sec.inertia = RHO * np.diag([i_yy + i_zz, i_yy, i_zz])
    sec.massPerLength = RHO * area
    return sec


def build(elements, offset):
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    sec = section()
    nodes = [mbs.AddNode(NodeRigidBodyRotVecLG(referenceCoordinates=[L * i / elements, 0, 0, 0, 0, 0]))
             for i in range(elements + 1)]
    beams = [mbs.AddObject(ObjectBeamGeometricallyExact(
        nodeNumbers=[nodes[i], nodes[i + 1]], length=L / elements, sectionData=sec))
        for i in range(elements)]
    ground = mbs.AddNode(NodePointGround(referenceCoordinates=[0, 0, 0]))
    mbs.AddObject(ObjectGround())
    for k in range(6):
        m0 = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=ground, coordinate=0))
        m1 = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=nodes[0], coordinate=k))
        mbs.AddObject(ObjectConnectorCoordinate(markerNumbers=[m0, m1]))
    ball = mbs.AddNode(NodePoint(referenceCoordinates=[L, offset, THICK / 2 + R_BALL],
                                 initialVelocities=[0, 0, -SPEED]))
    mbs.AddObject(ObjectMassPoint(physicsMass=M_BALL, nodeNumber=ball))
    e_star = E / (2 * (1 - NU ** 2))
    data = mbs.AddNode(NodeGenericData(initialCoordinates=[0.1, 0, 0, 0], numberOfDataCoordinates=4))
    if offset == 0:
        tip_marker = mbs.AddMarker(MarkerNodePosition(nodeNumber=nodes[-1]))
    else:
        tip_marker = mbs.AddMarker(MarkerBodyPosition(bodyNumber=beams[-1],
                                                      localPosition=[L / elements / 2, offset, 0]))
    ball_marker = mbs.AddMarker(MarkerNodePosition(nodeNumber=ball))
    mbs.AddObject(ObjectContactSphereSphere(
        markerNumbers=[ball_marker, tip_marker], nodeNumber=data,
        spheresRadii=[R_BALL, THICK / 2],
        contactStiffness=4.0 / 3.0 * e_star * R_BALL ** 0.5, contactStiffnessExponent=1.5,
        contactDamping=0.0, impactModel=0, restitutionCoefficient=1.0, dynamicFriction=0.0))
    sensors = [mbs.AddSensor(SensorNode(nodeNumber=ball, storeInternal=True,
                                        outputVariableType=exu.OutputVariableType.Position)),
               mbs.AddSensor(SensorMarker(markerNumber=tip_marker, storeInternal=True,
                                          outputVariableType=exu.OutputVariableType.Position))]
    mbs.Assemble()
    return sc, mbs, sensors


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--elements", type=int, default=256)
    parser.add_argument("--end-time", type=float, default=0.001)
    parser.add_argument("--step", type=float, default=1e-6)
    parser.add_argument("--offset", type=float, default=0.0,
                        help="strike point across the width from the centreline (m), |offset| < width/2")
    args = parser.parse_args()
    if not abs(args.offset) < WIDTH / 2:
        parser.error(f"--offset must lie within the width, |offset| < {WIDTH / 2}")
    sc, mbs, sensors = build(args.elements, args.offset)
    s = exu.SimulationSettings()
    s.timeIntegration.endTime = args.end_time
    s.timeIntegration.numberOfSteps = int(round(args.end_time / args.step))
    s.timeIntegration.generalizedAlpha.spectralRadius = 0.9
    s.timeIntegration.newton.relativeTolerance = 1e-6
    s.timeIntegration.discontinuous.maxIterations = 1
    s.timeIntegration.discontinuous.ignoreMaxIterations = True
    s.timeIntegration.discontinuous.iterationTolerance = 1e10
    s.timeIntegration.verboseMode = 0
    s.linearSolverType = exu.LinearSolverType.EigenSparse
    s.solutionSettings.writeSolutionToFile = False
    s.solutionSettings.sensorsWritePeriod = args.step
    clock = time.perf_counter()
    mbs.SolveDynamic(s)
    wall = time.perf_counter() - clock
    ball = mbs.GetSensorStoredData(sensors[0])
    tip = mbs.GetSensorStoredData(sensors[1])
    t = ball[:, 0]
    gap = np.linalg.norm(ball[:, 1:4] - tip[:, 1:4], axis=1) - R_BALL - THICK / 2
    e_star = E / (2 * (1 - NU ** 2))
    force = 4.0 / 3.0 * e_star * R_BALL ** 0.5 * np.clip(-gap, 0, None) ** 1.5
    print(f"exudyn {exu.__version__}: {args.elements} elements, {len(t) - 1} steps, "
          f"solve wall time {wall:.4f} s")
    if args.offset != 0:
        print(f"offset {args.offset * 1e3:.2f} mm across the width")
    touching = force > 0
    edges = np.flatnonzero(np.diff(touching.astype(int)))
    starts = [i + 1 for i in edges if not touching[i]]
    if touching[0]:
        starts = [0] + starts
    for k, i in enumerate(starts):
        j = i
        while j < len(t) and touching[j]:
            j += 1
        # Linear interpolation of the gap's zero crossings at both ends.
        def crossing(a, b):
            return t[a] + (t[b] - t[a]) * gap[a] / (gap[a] - gap[b])
        t0 = 0.0 if i == 0 else crossing(i - 1, i)
        t1 = crossing(j - 1, j) if j < len(t) else t[-1]
        print(f"contact {k + 1}: start {t0 * 1e6:.2f} us, duration {(t1 - t0) * 1e6:.2f} us, "
              f"peak {force[i:j].max():.1f} N")


if __name__ == "__main__":
    main()
