#!/usr/bin/python3
"""stream_poses.py: a sweepd client in Python that streams a BVH clip as poses.

The Python twin of client_examples/stream_poses.cpp, with the standard library and Debian's
python3-flatbuffers only (run it with /usr/bin/python3; Python 3.11, no numpy).

  /usr/bin/python3 client_examples/stream_poses.py --bvh clip.bvh
      [--host 127.0.0.1] [--port 7878] [--unix SOCKET] [--token T | --token-file FILE]
      [--tls [--tls-ca CA.pem] [--tls-cert C.pem --tls-key K.pem]] [--allow-plaintext]
      [--model NAME | --model-file body.glb] [--bvh-scale 0.056444]
      [--frames N] [--first-frame F] [--flat-out] [--latest-wins] [--float16]
      [--dump-poses poses.jsonl] [--protocol-dir DIR]

1. Connect (TCP HOST:PORT, or --unix SOCKET), Hello with the token (InOrder, or LatestWins
   with --latest-wins), read Welcome. With --tls (implied by --tls-ca and --tls-cert) the TCP
   connection is TLS (Python's ssl module): TLS 1.2 at least, the server's certificate checked
   against --tls-ca (default: the system's CAs) and the host name or address; --tls-cert and
   --tls-key offer a client certificate (sweepd's --tls-client-ca). A token is not sent over
   plain TCP to a host that is not loopback unless --allow-plaintext.
2. The model: --model-file uploads a .glb (LoadModel with bytes, stored under --model or
   the file's name); otherwise LoadModel by name (--model, default the server's
   "mannequin"). ModelInfo gives the joint order and,
   since protocol 1.1, the rest skeleton and floor height.
3. Read the BVH clip (CMU units: --bvh-scale 0.056444 turns them into metres) and retarget it
   onto the model's skeleton exactly as motion/retarget.cpp does (joints matched by name, rig
   role and hierarchy; rotations relative to each side's rest pose; root translation scaled
   by the hip-height ratio).
4. Stream frames F .. F+N-1 at the clip's frame rate, or --flat-out as fast as the server
   answers with at most Welcome.max_poses_in_flight poses in flight (a reader thread takes
   the replies). Positions come back as float32, or float16 with --float16.
5. Print poses sent/answered/dropped/errors, round-trip latency percentiles and the
   server's own deformation p50 (from Stats), like the C++ client.

--dump-poses FILE writes one JSON line per frame sent: {"frame", "rotations": [[x, y, z, w],
...] in model joint order, "root_translation": [x, y, z]} (the values before float32
rounding on the wire).

The generated protocol package (flatc --python, built by the CMake target
sweep_protocol_python into <build>/protocol/python) is found by --protocol-dir DIR, else the
environment variable SWEEPD_PROTOCOL_PYTHON, else build/release/protocol/python in this
repository.

Exit codes: 0 every pose answered; 1 some poses answered with an Error; 2 bad arguments or
input (BVH file, model file, protocol package); 3 the server is unreachable or the connection
broke; 4 the server refused (wrong token, unknown model, model load failed, ...).

Unlike the C++ library, a skeleton whose joint names fit no naming convention gets no rig
map here (the library would guess one from the geometry): such joints match by name and
hierarchy only, and the root translation is scaled by the plain pelvis height.
"""

import argparse
import importlib
import json
import math
import ipaddress
import os
import select
import socket
import ssl
import struct
import sys
import threading
import time
import types

EXIT_POSE_ERRORS, EXIT_BAD_INPUT, EXIT_CONNECTION, EXIT_REFUSED = 1, 2, 3, 4
CMU_TO_METRES = 0.056444


class BadInput(Exception):
    """A bad argument or input file: exit code 2."""


class ConnectionLost(Exception):
    """The server cannot be reached or the connection broke: exit code 3."""


class ServerError(Exception):
    """The server answered with an Error: exit code 4."""


# ---------------------------------------------------------------------------------------
# Quaternions (w, x, y, z) and vectors (x, y, z) as tuples, with glm's conventions.

IDENTITY = (1.0, 0.0, 0.0, 0.0)


def q_mul(a, b):
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return (aw * bw - ax * bx - ay * by - az * bz,
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw)


def q_normalize(q):
    length = math.sqrt(sum(c * c for c in q))
    return IDENTITY if length <= 0.0 else tuple(c / length for c in q)


def q_inverse(q):
    w, x, y, z = q
    dot = w * w + x * x + y * y + z * z
    return (w / dot, -x / dot, -y / dot, -z / dot)


def q_axis_angle(axis, radians):
    s = math.sin(radians / 2.0)
    return (math.cos(radians / 2.0), axis[0] * s, axis[1] * s, axis[2] * s)


def cross(u, v):
    return (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])


def dot(u, v):
    return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]


def add(u, v):
    return (u[0] + v[0], u[1] + v[1], u[2] + v[2])


def sub(u, v):
    return (u[0] - v[0], u[1] - v[1], u[2] - v[2])


def scale(u, s):
    return (u[0] * s, u[1] * s, u[2] * s)


def length(u):
    return math.sqrt(dot(u, u))


def normalize(u):
    return scale(u, 1.0 / length(u))


def q_rotate(q, v):
    """q * v for a unit quaternion, as glm computes it."""
    xyz = q[1:]
    uv = cross(xyz, v)
    uuv = cross(xyz, uv)
    return add(v, scale(add(scale(uv, q[0]), uuv), 2.0))


def shortest_arc(u, v):
    """The rotation taking unit vector u onto unit vector v by the shortest arc."""
    c = dot(u, v)
    if c < -1.0 + 1e-6:  # opposite: half a turn about any axis orthogonal to u
        axis = cross(u, (1.0, 0.0, 0.0))
        if dot(axis, axis) < 1e-6:
            axis = cross(u, (0.0, 1.0, 0.0))
        return q_axis_angle(normalize(axis), math.pi)
    axis = cross(u, v)
    return q_normalize((1.0 + c, axis[0], axis[1], axis[2]))


# ---------------------------------------------------------------------------------------
# Skeletons: joints parents-first, each with a name, a parent index (-1 for a root) and a
# rest transform local to the parent.

class Joint:
    def __init__(self, name, parent, translation, rotation=IDENTITY, scaling=(1.0, 1.0, 1.0)):
        self.name, self.parent = name, parent
        self.translation, self.rotation, self.scaling = translation, rotation, scaling


def children(joints, j):
    return [c for c, joint in enumerate(joints) if joint.parent == j]


def find_joint(joints, name):
    for j, joint in enumerate(joints):
        if joint.name == name:
            return j
    return -1


def world_rest_positions(joints):
    """World rest position of every joint, composing local T * R * S matrices (3 x 4)."""
    world = []
    for joint in joints:
        w, x, y, z = joint.rotation
        rotation = ((1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)),
                    (2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)),
                    (2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)))
        local = [[rotation[r][c] * joint.scaling[c] for c in range(3)] + [joint.translation[r]]
                 for r in range(3)]
        if joint.parent < 0:
            world.append(local)
            continue
        parent = world[joint.parent]
        world.append([[sum(parent[r][k] * local[k][c] for k in range(3)) +
                       (parent[r][3] if c == 3 else 0.0) for c in range(4)] for r in range(3)])
    return [(m[0][3], m[1][3], m[2][3]) for m in world]


def is_strict_ancestor(joints, ancestor, joint):
    """deform/model/joint_paths.h: True when `ancestor` lies strictly above `joint`."""
    if not (0 <= ancestor < len(joints) and 0 <= joint < len(joints)):
        return False
    j = joints[joint].parent
    while j >= ancestor:
        if j == ancestor:
            return True
        j = joints[j].parent
    return False


def path_down(joints, ancestor, joint):
    """The joints from `ancestor` down to `joint`, ancestor first; [] when not above it."""
    if not (0 <= ancestor < len(joints) and 0 <= joint < len(joints)):
        return []
    path, j = [], joint
    while j >= ancestor:
        path.append(j)
        if j == ancestor:
            return path[::-1]
        j = joints[j].parent
    return []


def common_ancestor(joints, a, b):
    if not (0 <= a < len(joints) and 0 <= b < len(joints)):
        return -1
    while a != b and a >= 0 and b >= 0:  # parents-first: lift the larger index
        if a > b:
            a = joints[a].parent
        else:
            b = joints[b].parent
    return a if a == b else -1


# ---------------------------------------------------------------------------------------
# Rig maps from joint names (deform/rig/rig_naming.cpp): which joints are the pelvis, chest,
# head and limb roles. Only what retargeting needs: roles, torso chain, validation.

# (name, pelvis prefix, side spellings, pelvis, head, clavicle, upper arm, forearm, hand,
#  hip, thigh, shin, foot, toe); '*' stands for the side spelling.
NAMING_CONVENTIONS = [
    ("mixamo", "mixamorig", [("Left", "Right")], ["Hips"], ["Head"],
     ["*Shoulder"], ["*Arm"], ["*ForeArm"], ["*Hand"],
     [], ["*UpLeg"], ["*Leg"], ["*Foot"], ["*ToeBase"]),
    ("cmu_motionbuilder", "", [("Left", "Right"), ("L", "R")], ["Hips"], ["Head"],
     ["*Shoulder"], ["*Arm"], ["*ForeArm"], ["*Hand"],
     ["*HipJoint"], ["*UpLeg"], ["*Leg"], ["*Foot"], ["*ToeBase"]),
    ("cmu_3dsmax", "", [("Left", "Right"), ("L", "R")], ["Hips"], ["Head"],
     ["*Collar"], ["*Shoulder"], ["*Elbow"], ["*Wrist"],
     [], ["*Hip"], ["*Knee"], ["*Ankle"], ["*Toe"]),
    ("unreal", "", [("l", "r")], ["pelvis"], ["head"],
     ["clavicle_*"], ["upperarm_*"], ["lowerarm_*"], ["hand_*"],
     [], ["thigh_*"], ["calf_*"], ["foot_*"], ["ball_*"]),
    ("rigify", "", [("L", "R")], ["spine"], ["spine.006", "head"],
     ["shoulder.*"], ["upper_arm.*"], ["forearm.*"], ["hand.*"],
     [], ["thigh.*"], ["shin.*"], ["foot.*"], ["toe.*"]),
    ("smpl", "", [("L", "R"), ("Left", "Right")], ["Pelvis"], ["Head"],
     ["*_Collar"], ["*_Shoulder"], ["*_Elbow"], ["*_Wrist"],
     [], ["*_Hip"], ["*_Knee"], ["*_Ankle"], ["*_Foot"]),
    ("vrm", "", [("left", "right")], ["hips"], ["head"],
     ["*Shoulder"], ["*UpperArm"], ["*LowerArm"], ["*Hand"],
     [], ["*UpperLeg"], ["*LowerLeg"], ["*Foot"], ["*Toes"]),
]
ARM_ROLES = ("clavicle", "upper", "lower", "hand")  # clavicle optional
LEG_ROLES = ("hip", "upper", "lower", "foot", "toe")  # hip and toe optional
REQUIRED_ROLES = ("upper", "lower", "hand", "foot")
LIMBS = ("left_arm", "right_arm", "left_leg", "right_leg")


class RigMap:
    def __init__(self, convention):
        self.convention = convention
        self.torso, self.neck, self.head = [], [], -1
        self.limbs = {}  # "left_arm" ... → {role: joint or -1}

    @property
    def pelvis(self):
        return self.torso[0] if self.torso else -1

    @property
    def chest(self):
        return self.torso[-1] if self.torso else -1


def joint_name_index(joints):
    """Lower-case names without a namespace ("mixamorig:", "Armature|") or "def-" prefix."""
    index = {}
    for j, joint in enumerate(joints):
        name = joint.name.lower()
        cut = max(name.rfind(":"), name.rfind("|"))
        name = name[cut + 1:]
        deform_bone = name.startswith("def-")
        if deform_bone:
            name = name[4:]
        if name not in index or deform_bone:  # Rigify's "DEF-x" wins over "x"
            index[name] = j
    return index


def find_pattern(index, patterns, side=""):
    for pattern in patterns:
        j = index.get(pattern.replace("*", side, 1).lower(), -1)
        if j >= 0:
            return j
    return -1


def validate_rig_map(rig, joints):
    """deform::validate_rig_map: '' when the map fits the skeleton, else the first problem."""
    if len(rig.torso) < 2:
        return "torso: needs at least two joints"
    for part, chain, first_parent in (("torso", rig.torso, -1), ("neck", rig.neck, rig.chest)):
        for i, j in enumerate(chain):
            expected = first_parent if i == 0 else chain[i - 1]
            if expected >= 0 and joints[j].parent != expected:
                return f"{part}: '{joints[j].name}' does not follow the hierarchy"
    if not rig.neck or rig.head != rig.neck[-1]:
        return "neck: does not end with the head"
    used = set(rig.torso) | set(rig.neck)
    if len(used) != len(rig.torso) + len(rig.neck):
        return "a joint is used twice"
    for limb in LIMBS:
        roles = rig.limbs[limb]
        previous = -1
        for role, j in roles.items():
            if j < 0:
                if role in REQUIRED_ROLES:
                    return f"{limb}: has no {role} joint"
                continue
            if previous >= 0 and not is_strict_ancestor(joints, previous, j):
                return f"{limb}: '{joints[j].name}' is not below '{joints[previous].name}'"
            previous = j
        root = roles["clavicle" if "clavicle" in roles else "hip"]
        root = root if root >= 0 else roles["upper"]
        if not is_strict_ancestor(joints, rig.pelvis, root):
            return f"{limb}: '{joints[root].name}' is not below the pelvis"
        for j in roles.values():
            if j >= 0:
                if j in used:
                    return f"{limb}: joint '{joints[j].name}' is used twice"
                used.add(j)
    return ""


def match_convention(index, joints, convention):
    """The roles one convention names (a RigMap) and the parts it misses."""
    (name, pelvis_prefix, sides, pelvis, head, clavicle, upper_arm, forearm, hand,
     hip, thigh, shin, foot, toe) = convention
    rig, missing = RigMap(name), []

    def sided(patterns, left):
        for side in sides:
            j = find_pattern(index, patterns, side[0] if left else side[1])
            if j >= 0:
                return j
        return -1

    pelvis_joint = find_pattern(index, pelvis)
    if pelvis_joint >= 0 and not joints[pelvis_joint].name.lower().startswith(pelvis_prefix):
        pelvis_joint = -1
    if pelvis_joint < 0:
        missing.append("pelvis")
    rig.head = find_pattern(index, head)
    if rig.head < 0:
        missing.append("head")
    for left, side in ((True, "left"), (False, "right")):
        arm = dict(zip(ARM_ROLES, (sided(p, left) for p in (clavicle, upper_arm, forearm, hand))))
        leg = dict(zip(LEG_ROLES, (sided(p, left) for p in (hip, thigh, shin, foot, toe))))
        rig.limbs[side + "_arm"], rig.limbs[side + "_leg"] = arm, leg
        for limb, roles in (("arm", arm), ("leg", leg)):
            if any(roles[r] < 0 for r in REQUIRED_ROLES if r in roles):
                missing.append(f"{side} {limb}")
    # A clavicle or hip link the convention does not name: the upper joint's parent, when only
    # this limb hangs below it (deform/rig/rig_naming.cpp, link_above).
    uppers = [rig.limbs[limb]["upper"] for limb in LIMBS] + [rig.head]
    for limb in LIMBS:
        roles = rig.limbs[limb]
        link = "clavicle" if limb.endswith("arm") else "hip"
        if roles["upper"] >= 0 and roles[link] < 0:
            others = [u for u in uppers if u != roles["upper"]]
            roles[link] = link_above(joints, roles["upper"], pelvis_joint, others)
    return rig, pelvis_joint, missing


def link_above(joints, upper, pelvis, others):
    """The parent of `upper` unless it is the pelvis or another limb or the head hangs below it."""
    parent = joints[upper].parent
    if parent < 0 or parent == pelvis:
        return -1
    for other in others:
        if other >= 0 and (other == parent or is_strict_ancestor(joints, parent, other)):
            return -1
    return parent


def complete_chains(rig, pelvis, joints):
    """Torso: pelvis up to the chest (where arms and head meet); neck: chest to head."""
    arm_root = [r["clavicle"] if r["clavicle"] >= 0 else r["upper"]
                for r in (rig.limbs["left_arm"], rig.limbs["right_arm"])]
    chest = common_ancestor(joints, common_ancestor(joints, *arm_root), rig.head)
    rig.torso = path_down(joints, pelvis, chest)
    if not rig.torso:
        return "the arms and the head do not meet below the pelvis"
    if chest == rig.head:
        return "the arms hang below the head"
    rig.neck = path_down(joints, chest, rig.head)[1:]
    return validate_rig_map(rig, joints)


def detect_rig_map(joints):
    """The RigMap of the first naming convention that fits, or (None, why)."""
    index = joint_name_index(joints)
    problem = "no naming convention fits"
    for convention in NAMING_CONVENTIONS:
        rig, pelvis, missing = match_convention(index, joints, convention)
        if missing:
            continue
        why = complete_chains(rig, pelvis, joints)
        if not why:
            return rig, ""
        problem = f"{convention[0]} names: {why}"
    return None, problem


def role_pairs(model, bvh):
    """(model joint, BVH joint) for every role both maps fill."""
    pairs = [(model.pelvis, bvh.pelvis), (model.chest, bvh.chest), (model.head, bvh.head)]
    for limb in LIMBS:
        roles = ARM_ROLES if limb.endswith("arm") else LEG_ROLES
        pairs += [(model.limbs[limb][r], bvh.limbs[limb][r]) for r in roles]
    return pairs


# ---------------------------------------------------------------------------------------
# BVH clips (io/bvh_load.cpp): hierarchy, channels in any order, one row per frame.

CHANNELS = ("Xposition", "Yposition", "Zposition", "Xrotation", "Yrotation", "Zrotation")
AXES = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))


class MotionJoint:
    def __init__(self, name, parent, channel_offset):
        self.name, self.parent = name, parent
        self.offset = (0.0, 0.0, 0.0)  # scaled
        self.channels = []  # indices into CHANNELS, in file order
        self.channel_offset = channel_offset
        self.end_site = None  # scaled End Site offset


class Motion:
    def __init__(self):
        self.joints, self.channel_count, self.frame_time, self.rows = [], 0, 0.0, []

    def local_pose(self, frame):
        """Local rotation (channels composed in file order) and translation of every joint."""
        row = self.rows[frame]
        rotations, translations = [], []
        for joint in self.joints:
            rotation, translation = IDENTITY, list(joint.offset)
            for c, channel in enumerate(joint.channels):
                value = row[joint.channel_offset + c]
                if channel >= 3:
                    rotation = q_mul(rotation, q_axis_angle(AXES[channel - 3], math.radians(value)))
                else:
                    translation[channel] += value
            rotations.append(rotation)
            translations.append(tuple(translation))
        return rotations, translations


class BvhParser:
    """Reads a BVH text; a malformed one raises BadInput naming the file, line and reason."""

    def __init__(self, text, source, length_scale):
        self.lines = text.lstrip("\ufeff").split("\n")
        self.source, self.scale = source, length_scale
        self.line, self.tokens = 0, []  # current line index and its remaining tokens
        self.motion = Motion()

    def fail(self, reason):
        raise BadInput(f"{self.source}:{self.line + 1}: {reason}")

    def next_token(self):
        while not self.tokens:
            if self.line + 1 >= len(self.lines):
                return ""
            self.line += 1
            self.tokens = self.lines[self.line].split()
        return self.tokens.pop(0)

    def number(self, what):
        token = self.next_token()
        try:
            value = float(token)
        except ValueError:
            self.fail(f"{what} needs a number, found {token!r}")
        if not math.isfinite(value):
            self.fail(f"{what} is not finite: {token!r}")
        return value

    def parse(self):
        if self.scale <= 0.0 or not math.isfinite(self.scale):
            raise BadInput(f"--bvh-scale must be finite and > 0, got {self.scale}")
        self.line, self.tokens = 0, self.lines[0].split()
        if self.next_token() != "HIERARCHY":
            self.fail("missing HIERARCHY at the start of the file")
        token = self.next_token()
        while token == "ROOT":
            self.parse_joint(-1)
            token = self.next_token()
        if not self.motion.joints:
            self.fail(f"expected ROOT after HIERARCHY, found {token!r}")
        if token != "MOTION":
            self.fail(f"expected ROOT or MOTION after the hierarchy, found {token!r}")
        self.parse_rows()
        return self.motion

    def parse_joint(self, parent):
        """After ROOT/JOINT: the name (rest of the line) and the block, nested joints too."""
        brace = self.tokens.index("{") if "{" in self.tokens else len(self.tokens)
        name, self.tokens = " ".join(self.tokens[:brace]), self.tokens[brace:]
        if not name:
            self.fail("a joint has no name")
        motion = self.motion
        index = len(motion.joints)
        joint = MotionJoint(name, parent, motion.channel_count)
        motion.joints.append(joint)
        if self.next_token() != "{":
            self.fail(f"expected '{{' after joint {name!r}")
        has_offset = False
        while True:
            token = self.next_token()
            if token == "}":
                if not has_offset:
                    self.fail(f"joint {name!r} has no OFFSET")
                return
            if token == "OFFSET":
                joint.offset = tuple(self.number(f"OFFSET of {name!r}") * self.scale
                                     for _ in range(3))
                has_offset = True
            elif token == "CHANNELS":
                count = self.number(f"CHANNELS count of {name!r}")
                if count < 0 or count != int(count):
                    self.fail(f"CHANNELS count of {name!r} is not a whole number")
                joint.channel_offset = motion.channel_count
                for c in range(int(count)):
                    channel = self.next_token()
                    if channel not in CHANNELS:
                        self.fail(f"bad channel name {channel!r} of joint {name!r} (expected "
                                  f"{', '.join(CHANNELS)})")
                    joint.channels.append(CHANNELS.index(channel))
                motion.channel_count += int(count)
            elif token == "JOINT":
                self.parse_joint(index)
            elif token == "End":
                if self.next_token() != "Site" or self.next_token() != "{":
                    self.fail(f"expected 'Site {{' after 'End' in joint {name!r}")
                if self.next_token() != "OFFSET":
                    self.fail(f"the End Site of {name!r} has no OFFSET")
                joint.end_site = tuple(self.number(f"End Site OFFSET of {name!r}") * self.scale
                                       for _ in range(3))
                if self.next_token() != "}":
                    self.fail(f"the End Site of {name!r} is not closed")
            elif token in ("", "MOTION", "ROOT"):
                self.fail(f"the block of joint {name!r} is not closed before "
                          f"{token or 'the end of the file'}")
            else:
                self.fail(f"unknown keyword {token!r} in joint {name!r}")

    def parse_rows(self):
        motion = self.motion
        if self.next_token() != "Frames:":
            self.fail("missing 'Frames:' after MOTION")
        header_frames = self.number("'Frames:'")
        if self.next_token() != "Frame" or self.next_token() != "Time:":
            self.fail("missing 'Frame Time:' after 'Frames:'")
        motion.frame_time = self.number("'Frame Time:'")
        if motion.frame_time <= 0.0:
            self.fail("'Frame Time:' must be a positive number of seconds")
        if self.tokens:
            self.fail(f"unexpected text after the 'Frame Time:' value: {self.tokens}")
        value_scale = [1.0] * motion.channel_count  # positions scale like offsets
        for joint in motion.joints:
            for c, channel in enumerate(joint.channels):
                if channel < 3:
                    value_scale[joint.channel_offset + c] = self.scale
        for self.line in range(self.line + 1, len(self.lines)):
            values = self.lines[self.line].split()
            if not values:
                continue
            if len(values) != motion.channel_count:
                self.fail(f"frame {len(motion.rows)} (counting from 0) has {len(values)} "
                          f"values, expected {motion.channel_count} (one per channel)")
            try:
                row = [float(v) * s for v, s in zip(values, value_scale)]
            except ValueError:
                self.fail(f"frame {len(motion.rows)} (counting from 0) has a value that is "
                          "not a number")
            if not all(math.isfinite(v) for v in row):
                self.fail(f"frame {len(motion.rows)} (counting from 0) has NaN or infinity")
            motion.rows.append(row)
        if not motion.rows:
            raise BadInput(f"{self.source}: no frames (the header says {int(header_frames)})")


def load_bvh(path, length_scale):
    try:
        with open(path, encoding="utf-8", errors="replace") as file:
            text = file.read()
    except OSError as error:
        raise BadInput(f"{path}: {error.strerror or error}") from error
    return BvhParser(text, path, length_scale).parse()


# ---------------------------------------------------------------------------------------
# Retargeting (motion/retarget.cpp): the clip played on the model's skeleton. For a model
# joint m driven by BVH joint b: W_m(frame) = D_b(frame) * A_m * W_m(rest), with D_b the
# world rotation b undergoes from its rest pose and A_m the rotation taking m's rest bone
# onto b's; local rotations W_parent^-1 * W_m. The root goes to hip-height ratio times the
# BVH pelvis position.

class Retargeter:
    def __init__(self, motion, skeleton, model_floor):
        self.motion, self.skeleton = motion, skeleton
        self.warnings = []
        bvh = [Joint(j.name, j.parent, j.offset) for j in motion.joints]
        model_map = self.rig_map_or_warning(skeleton, "model")
        bvh_map = self.rig_map_or_warning(bvh, "BVH clip")
        self.match_joints(bvh, model_map, bvh_map)
        self.compute_alignments(bvh)
        self.compute_root_scale(bvh, model_map, bvh_map, model_floor)

    def rig_map_or_warning(self, joints, side):
        rig, why = detect_rig_map(joints)
        if rig is None:
            self.warnings.append(f"no rig map for the {side} ({why}): joints matched by name "
                                 "and hierarchy only")
        return rig

    def match_joints(self, bvh, model_map, bvh_map):
        model = self.skeleton
        self.bvh_of_model = [-1] * len(model)
        self.model_of_bvh = [-1] * len(bvh)

        def match(m, b):
            if m < 0 or b < 0 or self.bvh_of_model[m] != -1 or self.model_of_bvh[b] != -1:
                return False
            self.bvh_of_model[m], self.model_of_bvh[b] = b, m
            return True

        # Fingers and thumbs are not measured by mocap (their channels are noise): left out,
        # as motion/retarget.cpp does; the hand moves rigidly with the clip's hand joint.
        if bvh_map:
            hands = [bvh_map.limbs[arm]["hand"] for arm in ("left_arm", "right_arm")
                     if arm in bvh_map.limbs]
            left_out = [b for b in range(len(bvh)) if self.model_of_bvh[b] == -1 and
                        any(is_strict_ancestor(bvh, hand, b) for hand in hands)]
            for b in left_out:
                self.model_of_bvh[b] = -2  # left out: never matched below
            if left_out:
                self.warnings.append("the clip's fingers and thumbs are not driven (" +
                                     ", ".join(bvh[b].name for b in left_out) + ")")
        for m, joint in enumerate(model):  # same name
            match(m, find_joint(bvh, joint.name))
        if model_map and bvh_map:  # same rig role
            for m, b in role_pairs(model_map, bvh_map):
                match(m, b)
        changed = True  # the only unmatched child of matched joints on both sides
        while changed:
            changed = False
            for m in range(len(model)):
                b = self.bvh_of_model[m]
                if b < 0:
                    continue
                model_children = [c for c in children(model, m) if self.bvh_of_model[c] == -1]
                bvh_children = [c for c in children(bvh, b) if self.model_of_bvh[c] == -1]
                if len(model_children) == 1 and len(bvh_children) == 1:
                    changed |= match(model_children[0], bvh_children[0])
        # Toes are not measured either: matched, so they aim the foot, but not driven; the
        # model's toes keep their rest rotation relative to the foot.
        toes = [bvh_map.limbs[leg]["toe"] for leg in ("left_leg", "right_leg")
                if bvh_map and leg in bvh_map.limbs and bvh_map.limbs[leg]["toe"] >= 0]
        self.driven = [b >= 0 and not any(b == toe or is_strict_ancestor(bvh, toe, b)
                                          for toe in toes) for b in self.bvh_of_model]
        undriven = [bvh[b].name for m, b in enumerate(self.bvh_of_model)
                    if b >= 0 and not self.driven[m]]
        if undriven:
            self.warnings.append("the clip's toes are not driven (" + ", ".join(undriven) + ")")

    def compute_alignments(self, bvh):
        model = self.skeleton
        model_world, bvh_world = world_rest_positions(model), world_rest_positions(bvh)
        self.world_rest, self.alignment = [], []
        for m, joint in enumerate(model):
            rest = q_normalize(joint.rotation)
            parent = joint.parent
            self.world_rest.append(rest if parent < 0 else q_mul(self.world_rest[parent], rest))
            self.alignment.append(IDENTITY if parent < 0 else self.alignment[parent])
            b = self.bvh_of_model[m]
            if b < 0:
                continue
            # The nearest matched descendants whose BVH joints descend from b.
            bone_ends, stack = [], children(model, m)
            while stack:
                c = stack.pop()
                if self.bvh_of_model[c] < 0:
                    stack += children(model, c)
                elif is_strict_ancestor(bvh, b, self.bvh_of_model[c]):
                    bone_ends.append(c)
            if len(bone_ends) != 1:
                continue
            model_bone = sub(model_world[bone_ends[0]], model_world[m])
            bvh_bone = sub(bvh_world[self.bvh_of_model[bone_ends[0]]], bvh_world[b])
            if length(model_bone) < 1e-6 or length(bvh_bone) < 1e-6:
                continue
            self.alignment[m] = shortest_arc(normalize(model_bone), normalize(bvh_bone))

    def compute_root_scale(self, bvh, model_map, bvh_map, model_floor):
        self.bvh_pelvis = bvh_map.pelvis if bvh_map else 0
        self.model_pelvis = model_map.pelvis if model_map else 0
        model_world, bvh_world = world_rest_positions(self.skeleton), world_rest_positions(bvh)
        self.model_pelvis_rest = model_world[self.model_pelvis]
        clip_floor = min(min(p[1] for p in bvh_world),
                         min((p[1] + j.end_site[1] for p, j in zip(bvh_world, self.motion.joints)
                              if j.end_site), default=math.inf))
        bvh_height = hip_height(bvh_map, bvh_world, self.bvh_pelvis, clip_floor)
        model_height = hip_height(model_map, model_world, self.model_pelvis, model_floor)
        self.root_scale = 1.0
        if bvh_height > 0.0 and model_height > 0.0:
            self.root_scale = model_height / bvh_height
        else:
            self.warnings.append("no hip height on one side: root translation not scaled")

    def driven_joint_count(self):
        return sum(self.driven)

    def pose_at_frame(self, frame):
        """(local rotations in model order, root translation) for frame `frame`."""
        bvh_local, bvh_translation = self.motion.local_pose(frame)
        bvh_world, bvh_position = [], []
        for b, joint in enumerate(self.motion.joints):
            p = joint.parent
            if p < 0:
                bvh_world.append(bvh_local[b])
                bvh_position.append(bvh_translation[b])
            else:
                bvh_world.append(q_mul(bvh_world[p], bvh_local[b]))
                bvh_position.append(add(bvh_position[p], q_rotate(bvh_world[p], bvh_translation[b])))
        world, local = [], []
        for m, joint in enumerate(self.skeleton):
            b, parent = self.bvh_of_model[m], joint.parent
            if not self.driven[m]:  # keeps its rest rotation relative to its parent
                world.append(joint.rotation if parent < 0 else q_mul(world[parent], joint.rotation))
                local.append(joint.rotation)
                continue
            # BVH rest rotations are the identity, so the BVH world rotation is D_b itself.
            world.append(q_normalize(q_mul(q_mul(bvh_world[b], self.alignment[m]),
                                           self.world_rest[m])))
            local.append(q_normalize(world[m] if parent < 0 else
                                     q_mul(q_inverse(world[parent]), world[m])))
        root_rest = self.skeleton[0].translation
        root = sub(add(root_rest, scale(bvh_position[self.bvh_pelvis], self.root_scale)),
                   self.model_pelvis_rest)
        return local, root


def hip_height(rig, world, pelvis, floor):
    """Pelvis height above the floor on straight legs (mean of both legs), or plain height."""
    if rig is None:
        return world[pelvis][1] - floor
    total = 0.0
    for leg in (rig.limbs["left_leg"], rig.limbs["right_leg"]):
        upper, lower, foot = world[leg["upper"]], world[leg["lower"]], world[leg["foot"]]
        total += (world[pelvis][1] - upper[1] + length(sub(upper, lower)) +
                  length(sub(lower, foot)) + foot[1] - floor)
    return total / 2.0


# ---------------------------------------------------------------------------------------
# The wire: size-prefixed FlatBuffers frames "SWPD" (protocol/README.md).

PROTOCOL_MODULES = ("Body", "Bye", "Error", "ErrorCode", "Hello", "LoadModel", "Message",
                    "ModelInfo", "Pose", "PoseDelivery", "PosedVertices", "PositionFormat",
                    "Quat", "Stats", "StatsRequest", "Vec3", "Welcome")


def import_protocol(protocol_dir):
    """Puts the generated package on sys.path; its modules (and flatbuffers) in a namespace."""
    here = os.path.dirname(os.path.abspath(__file__))
    directory = (protocol_dir or os.environ.get("SWEEPD_PROTOCOL_PYTHON") or
                 os.path.normpath(os.path.join(here, "..", "build", "release", "protocol",
                                               "python")))
    if not os.path.isfile(os.path.join(directory, "sweepd", "protocol", "Message.py")):
        raise BadInput(f"no generated protocol package in {directory} (build the CMake target "
                       "sweep_protocol_python, then pass --protocol-dir <build>/protocol/python "
                       "or set SWEEPD_PROTOCOL_PYTHON)")
    sys.path.insert(0, directory)
    try:
        modules = {name: importlib.import_module("sweepd.protocol." + name)
                   for name in PROTOCOL_MODULES}
        modules["flatbuffers"] = importlib.import_module("flatbuffers")
    except ImportError as error:
        raise BadInput(f"cannot import the protocol package ({error}); run with /usr/bin/python3 "
                       "and Debian's python3-flatbuffers") from error
    return types.SimpleNamespace(**modules)


def error_code_name(pb, code):
    for name, value in vars(pb.ErrorCode.ErrorCode).items():
        if value == code and not name.startswith("_"):
            return name
    return f"code {code}"


def tls_context(options):
    """The client's TLS settings from --tls-ca, --tls-cert and --tls-key."""
    try:
        context = ssl.create_default_context(cafile=options.tls_ca)
        context.minimum_version = ssl.TLSVersion.TLSv1_2
        if options.tls_cert:
            context.load_cert_chain(options.tls_cert, options.tls_key)
    except (OSError, ssl.SSLError) as error:
        raise BadInput(f"TLS files (--tls-ca, --tls-cert, --tls-key): "
                       f"{error.strerror or error}") from error
    return context


class TlsSocket:
    """An SSLSocket that one thread reads while another writes (the ReplyReader and the sender):
    each OpenSSL call runs under a lock on a non-blocking socket, and the wait for the socket
    happens outside the lock (OpenSSL does not let two threads use one connection at once)."""

    def __init__(self, raw, context, host, address):
        self.socket = context.wrap_socket(raw, server_hostname=host,
                                          do_handshake_on_connect=False)
        self.socket.setblocking(False)
        self.lock = threading.Lock()
        try:
            self.call(self.socket.do_handshake)
        except ssl.SSLCertVerificationError as error:
            raise ConnectionLost(f"TLS handshake with {address}: its certificate is not accepted "
                                 f"({error.verify_message}; --tls-ca names the CA that signed "
                                 f"it, and it must be issued to {host})") from error

    def call(self, operation, *args):
        while True:
            with self.lock:
                try:
                    return operation(*args)
                except ssl.SSLWantReadError:
                    readable, writable = [self.socket], []
                except ssl.SSLWantWriteError:
                    readable, writable = [], [self.socket]
            select.select(readable, writable, [])

    def sendall(self, data):
        view = memoryview(data)
        while view:
            view = view[self.call(self.socket.send, view):]

    def recv_into(self, view):
        return self.call(self.socket.recv_into, view)

    def close(self):
        self.socket.close()


class Connection:
    """A blocking sweepd connection, plain or TLS: send frames, receive Messages."""

    def __init__(self, pb, host, port, unix_path, tls=None):
        self.pb, self.flatbuffers = pb, pb.flatbuffers
        self.address = unix_path or f"{host}:{port}"
        self.tls = tls is not None and not unix_path
        try:
            if unix_path:
                self.socket = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
                self.socket.connect(unix_path)
                self.loopback = True
            else:
                raw = socket.create_connection((host, int(port)), timeout=10)
                raw.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
                self.loopback = ipaddress.ip_address(raw.getpeername()[0]).is_loopback
                if self.tls:
                    self.socket = TlsSocket(raw, tls, host, self.address)
                else:
                    raw.settimeout(None)
                    self.socket = raw
        except OSError as error:
            raise ConnectionLost(f"cannot connect to {self.address}: "
                                 f"{error.strerror or error}") from error
        self.send_lock = threading.Lock()

    def send(self, builder, body_type, body, request_id=0):
        pb = self.pb
        pb.Message.Start(builder)
        pb.Message.AddRequestId(builder, request_id)
        pb.Message.AddBodyType(builder, body_type)
        pb.Message.AddBody(builder, body)
        builder.FinishSizePrefixed(pb.Message.End(builder), b"SWPD")
        try:
            with self.send_lock:
                self.socket.sendall(builder.Output())
        except OSError as error:
            raise ConnectionLost(f"{self.address}: send failed: "
                                 f"{error.strerror or error}") from error

    def receive_into(self, view):
        """Fills the memoryview `view` from the socket."""
        got = 0
        while got < len(view):
            try:
                n = self.socket.recv_into(view[got:])
            except OSError as error:
                raise ConnectionLost(f"{self.address}: {error.strerror or error}") from error
            if n == 0:
                raise ConnectionLost(f"{self.address}: the server closed the connection")
            got += n

    def receive(self):
        """The next Message (prefix and body kept together: alignment counts from byte 0)."""
        prefix = bytearray(4)
        self.receive_into(memoryview(prefix))
        (size,) = struct.unpack("<I", prefix)
        frame = prefix + bytearray(size)
        self.receive_into(memoryview(frame)[4:])
        if size < 8 or not self.pb.Message.Message.MessageBufferHasIdentifier(frame, 0, True):
            raise ConnectionLost(f"{self.address}: a frame without the SWPD identifier")
        return self.pb.Message.Message.GetRootAs(frame, 4)

    def body(self, message, table):
        body = table()
        body.Init(message.Body().Bytes, message.Body().Pos)
        return body

    def expect(self, name):
        """The next Message's body as the table `name`; an Error raises ServerError."""
        pb = self.pb
        message = self.receive()
        if message.BodyType() == pb.Body.Body.Error:
            error = self.body(message, pb.Error.Error)
            raise ServerError(f"server error {error_code_name(pb, error.Code())}: "
                              f"{error.Message().decode()}")
        if message.BodyType() != getattr(pb.Body.Body, name):
            raise ConnectionLost(f"{self.address}: expected {name}, got body type "
                                 f"{message.BodyType()}")
        return self.body(message, getattr(getattr(pb, name), name))

    def hello(self, token, latest_wins, allow_plaintext=False):
        if token and not self.tls and not self.loopback and not allow_plaintext:
            raise BadInput(f"{self.address}: refusing to send the token over plain TCP to a host "
                           f"that is not loopback; connect with --tls (sweepd's --tls-cert/"
                           f"--tls-key), or pass --allow-plaintext on a private network")
        pb, builder = self.pb, self.flatbuffers.Builder(256)
        token_offset = builder.CreateString(token)
        name = builder.CreateString("stream_poses.py")
        pb.Hello.Start(builder)
        pb.Hello.AddVersionMajor(builder, 1)
        pb.Hello.AddVersionMinor(builder, 1)
        pb.Hello.AddAuthToken(builder, token_offset)
        pb.Hello.AddClientName(builder, name)
        pb.Hello.AddDelivery(builder, pb.PoseDelivery.PoseDelivery.LatestWins if latest_wins
                             else pb.PoseDelivery.PoseDelivery.InOrder)
        self.send(builder, pb.Body.Body.Hello, pb.Hello.End(builder), request_id=1)
        try:
            return self.expect("Welcome")
        except ConnectionLost as error:
            if self.tls:
                raise
            # A TLS listener drops a plaintext Hello without a reply.
            raise ConnectionLost(f"{error} (closed before Welcome: if sweepd has --tls-cert, "
                                 f"connect with --tls)") from error

    def load_model(self, name, glb):
        pb, builder = self.pb, self.flatbuffers.Builder(1024 + len(glb))
        gltf = builder.CreateByteVector(glb) if glb else None
        name_offset = builder.CreateString(name)
        pb.LoadModel.Start(builder)
        pb.LoadModel.AddName(builder, name_offset)
        if gltf is not None:
            pb.LoadModel.AddGltf(builder, gltf)
        self.send(builder, pb.Body.Body.LoadModel, pb.LoadModel.End(builder), request_id=2)
        return self.expect("ModelInfo")

    def stats(self):
        pb, builder = self.pb, self.flatbuffers.Builder(64)
        pb.StatsRequest.Start(builder)
        self.send(builder, pb.Body.Body.StatsRequest, pb.StatsRequest.End(builder), request_id=3)
        return self.expect("Stats")

    def close(self, reason):
        pb, builder = self.pb, self.flatbuffers.Builder(64)
        text = builder.CreateString(reason)
        pb.Bye.Start(builder)
        pb.Bye.AddReason(builder, text)
        self.send(builder, pb.Body.Body.Bye, pb.Bye.End(builder))
        self.socket.close()


def rest_skeleton(info):
    """client/model_skeleton.cpp: the served model's rest skeleton from ModelInfo (1.1)."""
    count = info.JointNamesLength()
    if (info.JointRestTranslationsIsNone() or info.JointRestRotationsIsNone() or
            info.JointRestScalesIsNone()):
        raise ServerError("ModelInfo carries no rest skeleton (the server speaks protocol 1.0)")
    if any(n != count for n in (info.JointParentsLength(), info.JointRestTranslationsLength(),
                                info.JointRestRotationsLength(), info.JointRestScalesLength())):
        raise ServerError("ModelInfo's joint arrays differ in length")
    joints = []
    for j in range(count):
        t, r, s = info.JointRestTranslations(j), info.JointRestRotations(j), info.JointRestScales(j)
        joints.append(Joint(info.JointNames(j).decode(), info.JointParents(j),
                            (t.X(), t.Y(), t.Z()), (r.W(), r.X(), r.Y(), r.Z()),
                            (s.X(), s.Y(), s.Z())))
        if not -1 <= joints[j].parent < j:
            raise ServerError(f"ModelInfo's skeleton is unusable: joint {j} "
                              f"('{joints[j].name}') has parent {joints[j].parent}")
    return joints


# ---------------------------------------------------------------------------------------
# Streaming.

def build_pose(connection, model_id, sequence, rotations, root, float16):
    """A Pose frame's builder and its body (FlatBuffers for Python has no Builder.Clear)."""
    pb, builder = connection.pb, connection.flatbuffers.Builder(64 + 16 * len(rotations))
    pb.Pose.StartRotationsVector(builder, len(rotations))
    for w, x, y, z in reversed(rotations):
        pb.Quat.CreateQuat(builder, x, y, z, w)
    rotation_vector = builder.EndVector()
    pb.Pose.Start(builder)
    pb.Pose.AddModelId(builder, model_id)
    pb.Pose.AddSequence(builder, sequence)
    pb.Pose.AddClientTimeNs(builder, time.monotonic_ns())
    pb.Pose.AddRotations(builder, rotation_vector)
    pb.Pose.AddRootTranslation(builder, pb.Vec3.CreateVec3(builder, *root))
    pb.Pose.AddPositions(builder, pb.PositionFormat.PositionFormat.Float16 if float16
                         else pb.PositionFormat.PositionFormat.Float32)
    return builder, pb.Pose.End(builder)


class ReplyReader(threading.Thread):
    """Takes the replies to poses 1..last_sequence; frees a window slot per reply (InOrder)."""

    def __init__(self, connection, last_sequence, slots):
        super().__init__(daemon=True)
        self.connection, self.last_sequence, self.slots = connection, last_sequence, slots
        self.latencies_ms, self.answered, self.dropped, self.errors = [], 0, 0, 0
        self.failure = None

    def run(self):
        pb, last = self.connection.pb, 0
        try:
            while last < self.last_sequence:
                message = self.connection.receive()
                sequence = 0
                if message.BodyType() == pb.Body.Body.PosedVertices:
                    reply = self.connection.body(message, pb.PosedVertices.PosedVertices)
                    sequence = reply.Sequence()
                    self.latencies_ms.append((time.monotonic_ns() - reply.ClientTimeNs()) * 1e-6)
                    self.answered += 1
                    self.dropped += reply.DroppedBefore()
                elif message.BodyType() == pb.Body.Body.Error:
                    error = self.connection.body(message, pb.Error.Error)
                    sequence = error.Sequence()
                    self.errors += 1
                    print(f"error {error_code_name(pb, error.Code())}: {error.Message().decode()}",
                          file=sys.stderr)
                    if error.Fatal():
                        raise ServerError(f"server error {error_code_name(pb, error.Code())}: "
                                          f"{error.Message().decode()}")
                last = max(last, sequence)
                if self.slots:
                    self.slots.release()
        except (ConnectionLost, ServerError) as failure:
            self.failure = failure
            if self.slots:  # unblock the sender
                for _ in range(self.last_sequence):
                    self.slots.release()


def percentile(values, q):
    values = sorted(values)
    return values[int(q * (len(values) - 1))] if values else 0.0


def run(options):
    if options.frames < 0 or options.first_frame < 0:
        raise BadInput("--frames and --first-frame must not be negative")
    glb = b""
    if options.model_file:
        try:
            with open(options.model_file, "rb") as file:
                glb = file.read()
        except OSError as error:
            raise BadInput(f"{options.model_file}: {error.strerror or error}") from error
    motion = load_bvh(options.bvh, options.bvh_scale)
    if options.first_frame >= len(motion.rows):
        raise BadInput(f"--first-frame {options.first_frame} is outside the clip's "
                       f"{len(motion.rows)} frames")
    pb = import_protocol(options.protocol_dir)

    tls = tls_context(options) if options.tls else None
    connection = Connection(pb, options.host, options.port, options.unix, tls)
    window = connection.hello(options.token, options.latest_wins,
                              options.allow_plaintext).MaxPosesInFlight()
    name = options.model or (os.path.basename(options.model_file) if options.model_file
                             else "mannequin")
    info = connection.load_model(name, glb)
    model_id = info.ModelId()
    clip = Retargeter(motion, rest_skeleton(info), info.FloorHeight())
    print(f"model {model_id}: {info.VertexCount()} vertices, {info.JointNamesLength()} joints "
          f"({clip.driven_joint_count()} driven by the clip)")
    for warning in clip.warnings:
        print(f"warning: {warning}", file=sys.stderr)

    available = len(motion.rows) - options.first_frame
    frames = min(options.frames, available) if options.frames > 0 else available
    slots = None if options.latest_wins else threading.Semaphore(max(window, 1))
    reader = ReplyReader(connection, frames, slots)
    reader.start()
    dump = open(options.dump_poses, "w", encoding="utf-8") if options.dump_poses else None
    start = time.monotonic()
    try:
        for i in range(frames):
            frame = options.first_frame + i
            if not options.flat_out:
                delay = start + i * motion.frame_time - time.monotonic()
                if delay > 0:
                    time.sleep(delay)
            rotations, root = clip.pose_at_frame(frame)
            if dump:
                dump.write(json.dumps({"frame": frame,
                                       "rotations": [[x, y, z, w] for w, x, y, z in rotations],
                                       "root_translation": list(root)}) + "\n")
            if slots:
                slots.acquire()  # LatestWins: the server drops, we never wait
            if reader.failure:
                break
            builder, pose = build_pose(connection, model_id, i + 1, rotations, root,
                                       options.float16)
            connection.send(builder, pb.Body.Body.Pose, pose)
    finally:
        if dump:
            dump.close()
    reader.join()
    if reader.failure:
        raise reader.failure
    seconds = time.monotonic() - start

    # The server's own deformation time for this model: round trip / deformation = overhead.
    stats = connection.stats()
    deform_p50_ms = 0.0
    for m in range(stats.ModelsLength()):
        if stats.Models(m).ModelId() == model_id:
            deform_p50_ms = stats.Models(m).DeformLatency().P50Ns() * 1e-6
    connection.close("clip finished")

    latencies = reader.latencies_ms
    print(f"poses: sent {frames}, answered {reader.answered}, dropped {reader.dropped}, "
          f"errors {reader.errors} in {seconds:.2f} s ({reader.answered / seconds:.0f}/s)")
    print(f"round trip ms: p50 {percentile(latencies, 0.5):.3f}  "
          f"p90 {percentile(latencies, 0.9):.3f}  p99 {percentile(latencies, 0.99):.3f}  "
          f"max {percentile(latencies, 1.0):.3f}")
    ratio = percentile(latencies, 0.5) / deform_p50_ms if deform_p50_ms > 0 else 0.0
    print(f"server deformation ms: p50 {deform_p50_ms:.3f} "
          f"(round trip p50 / deformation p50 = {ratio:.2f})")
    return 0 if reader.errors == 0 else EXIT_POSE_ERRORS


class ArgumentParser(argparse.ArgumentParser):
    def error(self, message):
        self.print_usage(sys.stderr)
        raise BadInput(message)


def parse_arguments(argv):
    parser = ArgumentParser(description="Stream a BVH clip to sweepd as poses (see the top of "
                            "this file).")
    parser.add_argument("--bvh", required=True, help="the BVH clip")
    parser.add_argument("--bvh-scale", type=float, default=CMU_TO_METRES,
                        help="BVH length unit in metres (default: CMU's 0.056444)")
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--port", default="7878")
    parser.add_argument("--unix", help="a Unix socket path instead of TCP")
    token = parser.add_mutually_exclusive_group()
    token.add_argument("--token", default="", help="the daemon's auth token")
    token.add_argument("--token-file", help="read the token from the first line of FILE "
                       "(e.g. a mounted Secret)")
    parser.add_argument("--tls", action="store_true", help="connect with TLS")
    parser.add_argument("--tls-ca", help="PEM CA certificates to trust instead of the system's "
                        "(implies --tls)")
    parser.add_argument("--tls-cert", help="client certificate, PEM (implies --tls; needs "
                        "--tls-key)")
    parser.add_argument("--tls-key", help="the client certificate's private key, PEM")
    parser.add_argument("--allow-plaintext", action="store_true",
                        help="send the token over plain TCP to a host that is not loopback")
    parser.add_argument("--model", help="the model's name on the server (default: "
                        "\"mannequin\", or the uploaded file's name)")
    parser.add_argument("--model-file", help="a .glb to upload (stored under --model)")
    parser.add_argument("--frames", type=int, default=0, help="frames to send (0: to the end)")
    parser.add_argument("--first-frame", type=int, default=0)
    parser.add_argument("--flat-out", action="store_true", help="ignore the clip's frame rate")
    parser.add_argument("--latest-wins", action="store_true")
    parser.add_argument("--float16", action="store_true")
    parser.add_argument("--dump-poses", help="JSON lines of the poses sent")
    parser.add_argument("--protocol-dir", help="<build>/protocol/python")
    options = parser.parse_args(argv)
    if bool(options.tls_cert) != bool(options.tls_key):
        parser.error("--tls-cert and --tls-key go together")
    options.tls = options.tls or bool(options.tls_ca) or bool(options.tls_cert)
    if options.token_file:
        try:
            with open(options.token_file, encoding="utf-8") as file:
                options.token = file.readline().rstrip("\n")
        except OSError as error:
            parser.error(f"--token-file {options.token_file}: cannot read the file "
                         f"({error.strerror})")
    return options


def main(argv):
    exit_codes = {BadInput: EXIT_BAD_INPUT, ConnectionLost: EXIT_CONNECTION,
                  ServerError: EXIT_REFUSED}
    try:
        return run(parse_arguments(argv))
    except (BadInput, ConnectionLost, ServerError) as error:
        print(f"stream_poses.py: {error}", file=sys.stderr)
        return exit_codes[type(error)]
    except KeyboardInterrupt:
        print("stream_poses.py: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
