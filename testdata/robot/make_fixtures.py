#!/usr/bin/env python3
"""Golden fixtures for stance-robot, computed by Pinocchio (PyPI package `pin` 4.1.0).

For each model (the project's small humanoid `models/small_humanoid.urdf`, the same with three
joints locked at non-zero values, and JVRC-1 from PyPI `jvrc-description` 1.1.1 with its 12
finger joints locked at 0), at random configurations and velocities (fixed seed), it writes:
mass, CoM, CoM Jacobian, A_g (`ccrba`), dA_g/dt v (`computeCentroidalMomentumTimeVariation`
with a = 0), and for a few frames (feet, hands, ...) the placement, the frame Jacobians in WORLD,
LOCAL and LOCAL_WORLD_ALIGNED, and the classical acceleration with a = 0 (`J_dot v`) in the same
three frames; and the path terms of docs/math.md section 6 at (q, q_s = v, q_ss = a random vector):
p_s and p_ss are Pinocchio's CoM velocity and acceleration (`centerOfMass(q, v, a)`), l1 and l2
the angular parts of the centroidal momentum and of its rate
(`computeCentroidalMomentumTimeVariation(q, v, a)`); and `integrate(q, 0.3 v)`.

Regenerate (from the project root, with the virtualenv of scripts/setup-venv.sh --peers):

    "${STANCE_VENV:-.venv}/bin/python" testdata/robot/make_fixtures.py

Output: testdata/robot/{small_humanoid,small_humanoid_locked,jvrc1}.json (JSON, floats with 17
significant digits; matrices as lists of rows).
"""

import json
import os
import sys

import numpy as np
import pinocchio as pin

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
RF = {
    "world": pin.ReferenceFrame.WORLD,
    "local": pin.ReferenceFrame.LOCAL,
    "local_world_aligned": pin.ReferenceFrame.LOCAL_WORLD_ALIGNED,
}


def rows(m):
    return np.asarray(m).tolist()


def random_configuration(model, rng):
    """Base in a 2 m cube around the origin with a uniform random orientation; joints uniform
    within their limits (continuous joints: uniform angle)."""
    q = pin.neutral(model)
    for j in model.joints[1:]:
        iq = j.idx_q
        name = j.shortname()
        if name == "JointModelFreeFlyer":
            q[iq:iq + 3] = rng.uniform(-1.0, 1.0, 3)
            quat = rng.normal(size=4)
            q[iq + 3:iq + 7] = quat / np.linalg.norm(quat)
        elif name.startswith("JointModelRUB"):
            a = rng.uniform(-np.pi, np.pi)
            q[iq:iq + 2] = [np.cos(a), np.sin(a)]
        else:
            lo, hi = model.lowerPositionLimit[iq], model.upperPositionLimit[iq]
            q[iq] = rng.uniform(lo, hi)
    return q


def build(urdf, locked, fixed=False):
    if fixed:
        return pin.buildModelFromUrdf(urdf)
    full = pin.buildModelFromUrdf(urdf, pin.JointModelFreeFlyer())
    if not locked:
        return full
    q_ref = pin.neutral(full)
    ids = []
    for name, value in locked:
        jid = full.getJointId(name)
        j = full.joints[jid]
        if j.nq == 2:
            q_ref[j.idx_q:j.idx_q + 2] = [np.cos(value), np.sin(value)]
        else:
            q_ref[j.idx_q] = value
        ids.append(jid)
    return pin.buildReducedModel(full, ids, q_ref)


def fixture(name, urdf_rel, urdf, locked, frames, count, seed, fixed=False):
    model = build(urdf, locked, fixed)
    data = model.createData()
    rng = np.random.default_rng(seed)
    cases = []
    for _ in range(count):
        q = random_configuration(model, rng)
        v = rng.normal(size=model.nv)
        a = np.zeros(model.nv)
        pin.forwardKinematics(model, data, q, v, a)
        pin.updateFramePlacements(model, data)
        pin.computeJointJacobians(model, data, q)
        com = pin.centerOfMass(model, data, q, v)
        jcom = pin.jacobianCenterOfMass(model, data, q)
        ag = pin.ccrba(model, data, q, v)
        ag = np.array(ag)
        pin.computeCentroidalMomentumTimeVariation(model, data, q, v, a)
        dhg = np.concatenate([data.dhg.linear, data.dhg.angular])
        # path terms (docs/math.md section 6) at (q, q_s = v, q_ss = a_path): Pinocchio's CoM
        # velocity and acceleration, centroidal momentum and its rate with that acceleration
        a_path = rng.normal(size=model.nv)
        pin.centerOfMass(model, data, q, v, a_path)
        vcom, acom = data.vcom[0].copy(), data.acom[0].copy()
        pin.computeCentroidalMomentumTimeVariation(model, data, q, v, a_path)
        # inverse dynamics (model.gravity: (0, 0, -9.81)) at (q, v, a_path), and gravity alone
        tau = pin.rnea(model, data, q, v, a_path).copy()
        tau_g = pin.computeGeneralizedGravity(model, data, q).copy()
        path = {
            "q_ss": a_path.tolist(),
            "p_s": vcom.tolist(),
            "p_ss": acom.tolist(),
            "l1": np.asarray(data.hg.angular).tolist(),
            "l2": np.asarray(data.dhg.angular).tolist(),
        }
        # recompute kinematics for the frame quantities (ccrba/CMTV leave data consistent, but
        # be explicit)
        pin.forwardKinematics(model, data, q, v, a)
        pin.updateFramePlacements(model, data)
        pin.computeJointJacobians(model, data, q)
        frame_out = {}
        for fname in frames:
            fid = model.getFrameId(fname)
            assert fid < model.nframes, fname
            placement = data.oMf[fid]
            entry = {
                "rotation": rows(placement.rotation),
                "translation": placement.translation.tolist(),
            }
            for key, rf in RF.items():
                entry["jacobian_" + key] = rows(pin.getFrameJacobian(model, data, fid, rf))
                acc = pin.getFrameClassicalAcceleration(model, data, fid, rf)
                entry["classical_acceleration_" + key] = (
                    np.concatenate([acc.linear, acc.angular]).tolist())
            frame_out[fname] = entry
        cases.append({
            "q": q.tolist(),
            "v": v.tolist(),
            "mass": float(data.mass[0]),
            "com": np.asarray(com).tolist(),
            "com_jacobian": rows(jcom),
            "centroidal_map": rows(ag),
            "centroidal_map_dot_v": dhg.tolist(),
            "path_terms": path,
            "integrate_0_3_v": pin.integrate(model, q, 0.3 * v).tolist(),
            "rnea": tau.tolist(),
            "generalized_gravity": tau_g.tolist(),
            "frames": frame_out,
        })
    out = {
        "generator": "testdata/robot/make_fixtures.py",
        "pinocchio_version": pin.__version__,
        "numpy_version": np.__version__,
        "urdf": urdf_rel,
        "root_joint": "fixed" if fixed else "free_flyer",
        "locked": [[n, v] for n, v in locked],
        "seed": seed,
        "nq": model.nq,
        "nv": model.nv,
        "joint_names": list(model.names)[1:],
        "frames": frames,
        "cases": cases,
    }
    path = os.path.join(HERE, name + ".json")
    with open(path, "w") as f:
        json.dump(out, f, separators=(",", ":"))
        f.write("\n")
    print(f"{path}: {count} cases, nq={model.nq}, nv={model.nv}, {os.path.getsize(path)} bytes")


def main():
    small = os.path.join(ROOT, "models", "small_humanoid.urdf")
    small_frames = ["r_sole", "l_sole", "r_hand", "l_hand", "imu", "head", "torso_lift"]
    fixture("small_humanoid", "models/small_humanoid.urdf", small, [], small_frames, 24, 1)
    fixture("small_humanoid_fixed", "models/small_humanoid.urdf", small, [], small_frames, 8, 4,
            fixed=True)
    fixture("small_humanoid_locked", "models/small_humanoid.urdf", small,
            [("r_elbow", -0.7), ("neck", 0.4), ("torso_lift", 0.02)],
            ["r_sole", "l_sole", "r_hand", "l_hand", "imu", "head"], 8, 2)
    try:
        import jvrc_description
    except ImportError:
        sys.exit("jvrc_description is not installed: run scripts/setup-venv.sh --peers")
    fingers = ["R_UTHUMB", "R_LTHUMB", "R_UINDEX", "R_LINDEX", "R_ULITTLE", "R_LLITTLE",
               "L_UTHUMB", "L_LTHUMB", "L_UINDEX", "L_LINDEX", "L_ULITTLE", "L_LLITTLE"]
    fixture("jvrc1", "jvrc1.urdf from PyPI jvrc-description " + jvrc_description.__version__,
            jvrc_description.urdf_path, [(f, 0.0) for f in fingers],
            ["R_ANKLE_P_S", "L_ANKLE_P_S", "r_wrist", "l_wrist"], 24, 3)


if __name__ == "__main__":
    main()
