#!/usr/bin/env python3
"""MuJoCo harness of the stance project: executes a retimed whole-body motion on a simulated
robot and measures whether its contacts hold.

Usage: stance_mujoco.py INPUT.json REPORT.json [TRACE.csv]
       stance_mujoco.py --describe MODEL.xml QPOS.json OUT.json

(TRACE: per step, the time, the base height and its reference, the trunk's angle from its
reference, and the normal load and largest slip so far of every planned contact of the current
segment: for diagnosis. --describe: the model's bodies (mass, principal inertia), joints
(range) and box geoms (world corners of their face z = -size_z at the configuration QPOS), as
MuJoCo compiled them: for the tests that compare the model with the project's.)

INPUT is written by `stance simulate` (the Rust side, `stance_sim`): the MJCF model written from
the project's data, the reference trajectory in MuJoCo's coordinates at the simulation's time
step (qpos, qvel, qacc), the planned contact forces of every reference sample, the contact
schedule and the thresholds. The math of the control and of the measurements is in the docs of
`stance_sim`; in short:

- control at every step: tau = tau_ff + kp (q* - q) + kv (v* - qdot), with the inverse dynamics
  of the reference tau_ff = M(q*) a* + c(q*, v*) - sum_j J_j(q*)^T f_j (the planned contact forces
  f_j at their points); the PD part is in the actuators (integrated implicitly by MuJoCo);
- measured: slip of every loaded planned contact (site displacement in its surface's plane since
  it was loaded), |F_t| / F_n of the resultant of MuJoCo's contact forces on it, contact losses
  (a planned contact separated from its surface), unplanned contacts (when, how hard, how long
  loaded; a landing or lift-off that touches while the reference has that pair within the
  separation threshold is an early or late touch, reported apart), base and CoM errors, falls.
  Verdict: held iff no fall, no lost planned contact, no unplanned contact carrying load (more
  than the load threshold) longer than the loss time, and every slip below the bound.
"""

import json
import math
import sys
import time

import mujoco
import numpy as np


def quat_angle(a, b):
    """Angle (rad) between two unit quaternions (w, x, y, z)."""
    d = abs(float(np.dot(a, b)))
    return 2.0 * math.acos(min(1.0, d))


def describe(model_path, qpos_path, out_path):
    model = mujoco.MjModel.from_xml_path(model_path)
    data = mujoco.MjData(model)
    with open(qpos_path) as f:
        data.qpos[:] = json.load(f)
    mujoco.mj_forward(model, data)
    bodies = [{"name": model.body(i).name, "mass": float(model.body_mass[i]),
               "inertia": sorted(float(x) for x in model.body_inertia[i])}
              for i in range(1, model.nbody)]
    joints = [{"name": model.joint(i).name, "range": [float(x) for x in model.jnt_range[i]],
               "limited": bool(model.jnt_limited[i])} for i in range(model.njnt)]
    geoms = []
    for i in range(model.ngeom):
        if model.geom_type[i] != mujoco.mjtGeom.mjGEOM_BOX:
            continue
        size = model.geom_size[i]
        r = data.geom_xmat[i].reshape(3, 3)
        p = data.geom_xpos[i]
        corners = [(p + r @ np.array([sx * size[0], sy * size[1], -size[2]])).tolist()
                   for sx, sy in [(1, 1), (-1, 1), (-1, -1), (1, -1)]]
        geoms.append({"name": model.geom(i).name, "corners": corners})
    with open(out_path, "w") as f:
        json.dump({"bodies": bodies, "joints": joints, "geoms": geoms,
                   "total_mass": float(sum(model.body_mass))}, f)


def main(input_path, report_path, trace_path=None):
    with open(input_path) as f:
        inp = json.load(f)
    model = mujoco.MjModel.from_xml_path(inp["mjcf"])
    data = mujoco.MjData(model)
    ref = inp["reference"]
    th = inp["thresholds"]
    t_ref = np.array(ref["t"])
    qpos = np.array(ref["qpos"])
    qvel = np.array(ref["qvel"])
    qacc = np.array(ref["qacc"])
    com_ref = np.array(ref["com"])
    seg_of = np.array(ref["segment"])
    dt = model.opt.timestep
    kp, kv = inp["kp"], inp["kv"]
    weight = inp["mass"] * float(np.linalg.norm(inp["gravity"]))

    geom_id = {model.geom(i).name: i for i in range(model.ngeom)}
    robot_geoms = {i for i in range(model.ngeom) if model.geom_contype[i] == 1}
    site_id = {model.site(i).name: i for i in range(model.nsite)}
    root_body = model.jnt_bodyid[0]  # the free joint's body

    # actuators: their joint's qpos and dof addresses
    act_q = np.array([model.jnt_qposadr[model.actuator_trnid[i, 0]] for i in range(model.nu)])
    act_v = np.array([model.jnt_dofadr[model.actuator_trnid[i, 0]] for i in range(model.nu)])

    # feedforward at every reference sample: inverse dynamics with the planned contact forces
    ff = np.zeros((len(t_ref), model.nv))
    ffd = mujoco.MjData(model)
    jacp = np.zeros((3, model.nv))
    ma = np.zeros(model.nv)
    for k in range(len(t_ref)):
        ffd.qpos[:] = qpos[k]
        ffd.qvel[:] = qvel[k]
        mujoco.mj_forward(model, ffd)
        mujoco.mj_mulM(model, ffd, ma, qacc[k])
        tau = ma + ffd.qfrc_bias
        for c in ref["forces"][k]:
            body = model.geom_bodyid[geom_id[c["geom"]]]
            for p, fw in zip(c["points"], c["forces"]):
                mujoco.mj_jac(model, ffd, jacp, None, np.array(p, dtype=float), body)
                tau = tau - jacp.T @ np.array(fw, dtype=float)
        ff[k] = tau
    ff_residual = float(np.max(np.abs(ff[:, :6]))) if model.nv >= 6 else 0.0

    segments = inp["segments"]
    t_end = float(t_ref[-1])
    settle = th["settle"]
    # a reference that starts at rest is first held for a while (the contacts settle, and the
    # weight they carry is measured); one that starts in motion starts at once, at its speed
    at_rest = float(np.max(np.abs(qvel[0]))) < 1e-9
    preroll = 0.3 if at_rest else 0.0
    disturbance = inp.get("disturbance")

    def reference_at(t):
        """Linear interpolation of the reference at motion time t (clamped to its ends)."""
        if t <= t_ref[0]:
            return 0, 0, 0.0
        if t >= t_end:
            n = len(t_ref) - 1
            return n, n, 0.0
        i = int(np.searchsorted(t_ref, t, side="right") - 1)
        a = (t - t_ref[i]) / (t_ref[i + 1] - t_ref[i])
        return i, i + 1, a

    def segment_at(t):
        for s, seg in enumerate(segments):
            if t < seg["t_end"] or s == len(segments) - 1:
                return s
        return len(segments) - 1

    def near_switch(t):
        w = th["transition"]
        for seg in segments:
            if abs(t - seg["t_start"]) < w or abs(t - seg["t_end"]) < w:
                return True
        return False

    data.qpos[:] = qpos[0]
    data.qvel[:] = qvel[0]
    mujoco.mj_forward(model, data)
    standing = []

    # per planned contact (segment, surface): measurements
    per = {}
    for s, seg in enumerate(segments):
        for name, g, e in seg["stance"]:
            per[(s, name)] = {
                "segment": seg["number"], "surface": name, "environment": e.split(":", 1)[-1],
                "geom": geom_id[g], "env": geom_id[e], "site": site_id[g],
                "anchor": None, "max_slip": 0.0, "max_usage": 0.0,
                "min_normal": math.inf, "off_since": None, "longest_loss": 0.0,
            }
    unplanned = {}
    # landings and lift-offs the simulator makes early or late: a pair planned in the segment
    # before or after, touching while the reference has it within the separation threshold
    early_late = {}
    # the reference's own geometry, for the distance of such a pair in the plan
    data_ref = mujoco.MjData(model)
    planned_pairs = [
        {(geom_id[g], geom_id[e]) for _name, g, e in seg["stance"]} for seg in segments
    ]
    max_base, max_angle, max_com, fell = 0.0, 0.0, 0.0, False
    fall_reason = ""
    # what the viewer plays and marks: qpos every frame_dt of simulated time, and the events
    frame_every = max(1, int(round(inp.get("frame_dt", 0.02) / dt)))
    frames_t, frames_q, events = [], [], []

    def event(kind, t, position, text):
        events.append({"kind": kind, "t": float(t), "position": [float(x) for x in position], "text": text})
    force6 = np.zeros(6)
    steps_total = int(round((preroll + t_end + settle) / dt))
    trace = open(trace_path, "w") if trace_path else None
    wall0 = time.perf_counter()
    for step in range(steps_total):
        t = step * dt - preroll
        tm = min(max(t, 0.0), t_end)
        i, j, a = reference_at(tm)
        q_star = (1 - a) * qpos[i] + a * qpos[j]
        q_star[3:7] /= np.linalg.norm(q_star[3:7])
        moving = 0.0 <= t <= t_end
        v_star = ((1 - a) * qvel[i] + a * qvel[j]) if moving else np.zeros(model.nv)
        tau_ff = (1 - a) * ff[i] + a * ff[j]
        if not moving:
            # before and after the motion, which starts and ends at rest: hold its end sample
            tau_ff = ff[0] if t < 0 else ff[-1]
        data.ctrl[:] = q_star[act_q] + (kv / kp) * v_star[act_v] + tau_ff[act_v] / kp
        data.xfrc_applied[:] = 0.0
        if disturbance and disturbance["t_start"] <= t < disturbance["t_end"]:
            b = model.geom_bodyid[geom_id[disturbance["geom"]]]
            data.xfrc_applied[b, :3] = disturbance["force"]
        mujoco.mj_step(model, data)
        if t < 0:
            if t >= -0.1:
                # the weight the contacts carry while the robot stands still
                fz = 0.0
                for c in range(data.ncon):
                    con = data.contact[c]
                    mujoco.mj_contactForce(model, data, c, force6)
                    f_world = con.frame.reshape(3, 3).T @ force6[:3]
                    fz += abs(float(np.dot(f_world, np.array(inp["gravity"]) / -np.linalg.norm(inp["gravity"]))))
                standing.append(fz)
            continue
        # measurements
        s_now = segment_at(tm)
        planned = {(per[key]["geom"], per[key]["env"]): key for key in per if key[0] == s_now}
        unplanned_load = {}
        early_load = {}
        wrench = {key: np.zeros(3) for key in planned.values()}
        touching = set()
        ref_placed = False
        for c in range(data.ncon):
            con = data.contact[c]
            g1, g2 = con.geom1, con.geom2
            rg, eg = (g1, g2) if g1 in robot_geoms else (g2, g1)
            key = planned.get((rg, eg))
            if key is None:
                neighbours = [k for k in (s_now - 1, s_now + 1) if 0 <= k < len(segments)]
                if any((rg, eg) in planned_pairs[k] for k in neighbours):
                    if not ref_placed:
                        data_ref.qpos[:] = q_star
                        mujoco.mj_kinematics(model, data_ref)
                        ref_placed = True
                    gap = mujoco.mj_geomDistance(model, data_ref, rg, eg, 1.0, None)
                    if gap <= th["separation"]:
                        # a landing (or lift-off) within the separation threshold in the plan:
                        # in contact, by the same tolerance as a planned contact's loss
                        mujoco.mj_contactForce(model, data, c, force6)
                        seg = segments[s_now]
                        landing = s_now + 1 < len(segments) and (rg, eg) in planned_pairs[s_now + 1]
                        lifting = s_now > 0 and (rg, eg) in planned_pairs[s_now - 1]
                        if landing and lifting:
                            # planned on both sides: nearer the segment's end, a landing
                            landing = tm - seg["t_start"] > seg["t_end"] - tm
                        pair = (f"{model.geom(rg).name} / {model.geom(eg).name}",
                                seg["number"], "landed early" if landing else "lifted late")
                        if pair not in early_late:
                            event("early_touch" if landing else "late_lift", t, con.pos,
                                  f"{pair[0]} {pair[2]} in segment {pair[1]}")
                        e = early_late.setdefault(pair, [t, t, 0.0, 0.0, 0.0])
                        e[1] = t
                        e[2] = max(e[2], force6[0])
                        early_load[pair] = early_load.get(pair, 0.0) + force6[0]
                        continue
                if not near_switch(tm):
                    mujoco.mj_contactForce(model, data, c, force6)
                    pair = f"{model.geom(rg).name} / {model.geom(eg).name}"
                    if pair not in unplanned:
                        event("unplanned_contact", t, con.pos, f"{pair} touched (not planned)")
                    u = unplanned.setdefault(pair, [t, t, 0.0, 0.0, 0.0])
                    u[1] = t
                    u[2] = max(u[2], force6[0])
                    unplanned_load[pair] = unplanned_load.get(pair, 0.0) + force6[0]
                continue
            touching.add(key)
            mujoco.mj_contactForce(model, data, c, force6)
            # contact frame rows: normal (from geom1 to geom2), then tangents; the force on
            # the robot points from the environment into the robot
            f_world = con.frame.reshape(3, 3).T @ force6[:3]
            wrench[key] += f_world if rg == g2 else -f_world
        for key in planned.values():
            p = per[key]
            n = data.geom_xmat[p["env"]].reshape(3, 3)[:, 2]
            f = wrench[key]
            load = float(np.dot(f, n))
            ft = float(np.linalg.norm(f - load * n))
            p["min_normal"] = min(p["min_normal"], load)
            if load > th["load"] * weight:
                p["max_usage"] = max(p["max_usage"], ft / load)
            site = data.site_xpos[p["site"]].copy()
            if load > th["load"] * weight:
                if p["anchor"] is None:
                    p["anchor"] = site
                d = site - p["anchor"]
                slip = float(np.linalg.norm(d - np.dot(d, n) * n))
                if slip > th["max_slip"] >= p["max_slip"]:
                    event("slip", t, site, f"{p['surface']} slipped more than {th['max_slip'] * 1e3:.0f} mm "
                          f"on {p['environment']} in segment {p['segment']}")
                p["max_slip"] = max(p["max_slip"], slip)
            else:
                p["anchor"] = None
            # lost: separated from its surface (not merely unloaded: with two contacts the
            # simulator may share the load otherwise than the plan's minimum-norm forces)
            gap = mujoco.mj_geomDistance(model, data, p["geom"], p["env"], 1.0, None)
            if gap <= th["separation"] or near_switch(tm):
                p["off_since"] = None
            else:
                if p["off_since"] is None:
                    p["off_since"] = t
                # once per loss, when it outlasts the loss time
                if t - p["off_since"] > th["loss_time"] and p.get("reported") != p["off_since"]:
                    p["reported"] = p["off_since"]
                    event("contact_loss", p["off_since"], site, f"{p['surface']} lost on {p['environment']} "
                          f"in segment {p['segment']} (for more than {th['loss_time'] * 1e3:.0f} ms)")
                p["longest_loss"] = max(p["longest_loss"], t - p["off_since"])
        # unplanned support: an unplanned contact carrying load, and for how long (the same
        # for early landings and late lift-offs)
        for table, load in ((unplanned, unplanned_load), (early_late, early_load)):
            for pair, u in table.items():
                if load.get(pair, 0.0) > th["load"] * weight:
                    u[3] += dt
                    u[4] = max(u[4], u[3])
                else:
                    u[3] = 0.0
        loads = {key: float(np.dot(wrench[key], data.geom_xmat[per[key]["env"]].reshape(3, 3)[:, 2])) for key in planned.values()}
        if trace:
            trace.write(f"{t:.4f},{data.qpos[2]:.5f},{q_star[2]:.5f},{quat_angle(data.qpos[3:7], q_star[3:7]):.4f}," + ",".join(
                f"{per[key]['surface']}:{loads[key]:.1f}:{per[key]['max_slip'] * 1e3:.2f}mm" for key in planned.values()) + "\n")
        # base, CoM, fall
        base_err = float(np.linalg.norm(data.qpos[:3] - q_star[:3]))
        angle = quat_angle(data.qpos[3:7], q_star[3:7])
        com = data.subtree_com[root_body]
        ci, cj = com_ref[i], com_ref[j]
        com_err = float(np.linalg.norm(com - ((1 - a) * ci + a * cj)))
        max_base, max_angle, max_com = max(max_base, base_err), max(max_angle, angle), max(max_com, com_err)
        if step % frame_every == 0:
            frames_t.append(float(t))
            frames_q.append(data.qpos.tolist())
        if data.qpos[2] < q_star[2] - th["fall_height"] or angle > th["fall_tilt"]:
            fell = True
            fall_reason = f"fell at t = {t:.3f} s (base {q_star[2] - data.qpos[2]:.3f} m low, trunk {math.degrees(angle):.1f} deg off)"
            event("fall", t, data.qpos[:3], fall_reason)
            break
    wall = time.perf_counter() - wall0
    sim_time = step * dt
    if not frames_t or frames_t[-1] < t:
        frames_t.append(float(t))
        frames_q.append(data.qpos.tolist())
    events.sort(key=lambda e: e["t"])

    contacts = []
    for key, p in per.items():
        contacts.append({
            "segment": p["segment"], "surface": p["surface"], "environment": p["environment"],
            "max_slip_m": p["max_slip"], "max_friction_usage": p["max_usage"],
            "min_normal_force": p["min_normal"] if math.isfinite(p["min_normal"]) else 0.0,
            "longest_loss_s": p["longest_loss"],
        })
    max_slip = max((c["max_slip_m"] for c in contacts), default=0.0)
    losses = sum(1 for c in contacts if c["longest_loss_s"] > th["loss_time"])
    leaned = [(pair, u[4]) for pair, u in unplanned.items() if u[4] > th["loss_time"]]
    max_usage = max((c["max_friction_usage"] for c in contacts), default=0.0)
    if fell:
        held, reason = False, fall_reason
    elif losses:
        worst = max(contacts, key=lambda c: c["longest_loss_s"])
        held, reason = False, f"{losses} planned contact(s) lost (longest: {worst['surface']} on {worst['environment']} in segment {worst['segment']}, {worst['longest_loss_s'] * 1e3:.0f} ms)"
    elif leaned:
        pair, d = max(leaned, key=lambda x: x[1])
        held, reason = False, f"leaned on an unplanned contact: {pair} carried load for {d * 1e3:.0f} ms"
    elif max_slip > th["max_slip"]:
        worst = max(contacts, key=lambda c: c["max_slip_m"])
        held, reason = False, f"{worst['surface']} slipped {worst['max_slip_m'] * 1e3:.1f} mm on {worst['environment']} in segment {worst['segment']}"
    else:
        held, reason = True, f"held: largest slip {max_slip * 1e3:.2f} mm, no contact lost, no fall"
    report = {
        "held": held, "reason": reason, "max_slip_m": max_slip, "contact_losses": losses,
        "unplanned_contacts": [
            f"{pair}: from {u[0]:.3f} s to {u[1]:.3f} s, up to {u[2]:.1f} N, loaded for up to {u[4] * 1e3:.0f} ms"
            for pair, u in sorted(unplanned.items())
        ],
        "early_or_late_touches": [
            f"{pair} {kind} in segment {seg}: from {e[0]:.3f} s to {e[1]:.3f} s, up to "
            f"{e[2]:.1f} N, loaded for up to {e[4] * 1e3:.0f} ms"
            for (pair, seg, kind), e in sorted(early_late.items())
        ], "fell": fell, "max_base_error_m": max_base,
        "max_base_angle_rad": max_angle, "max_com_error_m": max_com,
        "max_friction_usage": max_usage,
        "max_feedforward_residual": ff_residual, "contacts": contacts,
        "sim_time_s": sim_time, "wall_s": wall, "wall_per_sim_s": wall / max(sim_time, 1e-9),
        "time_scale": inp["time_scale"], "mujoco_version": mujoco.__version__,
        "standing_load_ratio": (float(np.mean(standing)) / weight) if standing else None,
        "executed": {"t": frames_t, "qpos": frames_q},
        "events": events,
    }
    with open(report_path, "w") as f:
        json.dump(report, f, indent=1)


if __name__ == "__main__":
    if len(sys.argv) == 5 and sys.argv[1] == "--describe":
        describe(*sys.argv[2:])
    elif len(sys.argv) in (3, 4):
        main(*sys.argv[1:])
    else:
        sys.exit("usage: stance_mujoco.py INPUT.json REPORT.json [TRACE.csv]\n"
                 "       stance_mujoco.py --describe MODEL.xml QPOS.json OUT.json")
