"""The paper's tip impact in Exudyn: a planar geometrically exact beam struck by a point mass.

Peer measurement for `cargo xtask simulate` (see README.md in this folder). Not part of the build,
the tests or CI. Usage, in a virtual environment outside the repository:

    pip install exudyn numpy
    python validation/peers/exudyn_tip.py --elements 256 --end-time 0.001 --step 1e-6

It prints the wall time of the solve (not of building the model) and the contacts found from the
gap between the ball and the tip: start (us), duration (us) and peak force (N).
"""
import argparse
import time

import numpy as np
import exudyn as exu
from exudyn.itemInterface import (
    NodeRigidBody2D, NodePoint2D, NodePointGround, NodeGenericData, ObjectBeamGeometricallyExact2D,
    ObjectMassPoint2D, ObjectContactSphereSphere, ObjectGround, MarkerNodeCoordinate,
    MarkerNodePosition, ObjectConnectorCoordinate, SensorNode)

# The scene of validation/scenes/paper-tip.toml, gravity off.
L, WIDTH, THICK = 1.15, 0.025, 0.005
E, NU, RHO = 2.1e11, 0.3, 7850.0
R_BALL, M_BALL = 0.005, 0.009
SPEED = (2 * 9.81 * 0.2) ** 0.5
SHEAR_FACTOR = 5.0 / 6.0


def build(elements):
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    area, inertia = WIDTH * THICK, WIDTH * THICK ** 3 / 12
    g = E / (2 * (1 + NU))
    nodes = []
    for i in range(elements + 1):
        nodes.append(mbs.AddNode(NodeRigidBody2D(referenceCoordinates=[L * i / elements, 0, 0])))
    for i in range(elements):
        mbs.AddObject(ObjectBeamGeometricallyExact2D(
            nodeNumbers=[nodes[i], nodes[i + 1]], length=L / elements,
            massPerLength=RHO * area, crossSectionInertia=RHO * inertia,
            bendingStiffness=E * inertia, axialStiffness=E * area,
            shearStiffness=SHEAR_FACTOR * g * area))
    ground = mbs.AddNode(NodePointGround(referenceCoordinates=[0, 0, 0]))
    mbs.AddObject(ObjectGround())
    for k in range(3):
        m0 = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=ground, coordinate=0))
        m1 = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=nodes[0], coordinate=k))
        mbs.AddObject(ObjectConnectorCoordinate(markerNumbers=[m0, m1]))
    ball = mbs.AddNode(NodePoint2D(referenceCoordinates=[L, THICK / 2 + R_BALL],
                                   initialVelocities=[0, -SPEED]))
    mbs.AddObject(ObjectMassPoint2D(physicsMass=M_BALL, nodeNumber=ball))
    e_star = E / (2 * (1 - NU ** 2))
    data = mbs.AddNode(NodeGenericData(initialCoordinates=[0.1, 0, 0, 0], numberOfDataCoordinates=4))
    tip_marker = mbs.AddMarker(MarkerNodePosition(nodeNumber=nodes[-1]))
    ball_marker = mbs.AddMarker(MarkerNodePosition(nodeNumber=ball))
    mbs.AddObject(ObjectContactSphereSphere(
        markerNumbers=[ball_marker, tip_marker], nodeNumber=data,
        spheresRadii=[R_BALL, THICK / 2],
        contactStiffness=4.0 / 3.0 * e_star * R_BALL ** 0.5, contactStiffnessExponent=1.5,
        contactDamping=0.0, impactModel=0, restitutionCoefficient=1.0, dynamicFriction=0.0))
    sensors = [mbs.AddSensor(SensorNode(nodeNumber=n, storeInternal=True,
                                        outputVariableType=exu.OutputVariableType.Position))
               for n in (ball, nodes[-1])]
    mbs.Assemble()
    return sc, mbs, sensors


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--elements", type=int, default=256)
    parser.add_argument("--end-time", type=float, default=0.001)
    parser.add_argument("--step", type=float, default=1e-6)
    args = parser.parse_args()
    sc, mbs, sensors = build(args.elements)
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
    gap = np.hypot(ball[:, 1] - tip[:, 1], ball[:, 2] - tip[:, 2]) - R_BALL - THICK / 2
    e_star = E / (2 * (1 - NU ** 2))
    force = 4.0 / 3.0 * e_star * R_BALL ** 0.5 * np.clip(-gap, 0, None) ** 1.5
    print(f"exudyn {exu.__version__}: {args.elements} elements, {len(t) - 1} steps, "
          f"solve wall time {wall:.4f} s")
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
