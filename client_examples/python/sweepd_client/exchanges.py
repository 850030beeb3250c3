"""Exchanges: what Client and AsyncClient say to sweepd, written once without I/O.

Each request is a generator (an "exchange") that yields the steps it needs, Send(frame) or
Receive(table), and gets back the reply for a Receive (an Error reply is thrown into it as its
ServerError, a broken connection as ConnectionLost); it returns the request's result. A stream
(poses) also yields each Posed for its caller. Client runs exchanges over a blocking socket,
AsyncClient over asyncio streams: they share the frames, the replies' decoding, the models and
clips known on the connection, and the process-wide upload caches.

Rotations are local (parent-relative) unit quaternions in the model's joint order
(Model.joint_names), as an array of shape (joints, 4) in x, y, z, w order; None is the rest
pose. `model` arguments take a Model, a model id or a model name (loaded on first use).

encoding= chooses how positions (and normals) travel: "float32" (exact), "float16" (half the
bytes, error up to 2^-11 relative: under 1 mm on a 2 m body) or "meshopt" (protocol 1.5:
positions on a 0.18 mm grid through meshoptimizer's vertex codec, error ≤ 0.09 mm, normals as
8-bit; needs meshoptimizer's shared library, see sweepd_client.meshopt). Every encoding comes
back as the same float32 arrays; float16=True is encoding="float16".

Replies in shared memory (protocol 1.10; Client on a Unix socket only): map_shared_memory(size)
maps a region the server writes float32 replies into; pose(shared_offset=N) has that pose
written at byte N, and poses(shared=True) cycles the poses in flight over slots of one reply
each. Their Posed arrays are then read-only views of the region, valid until the server writes
that place again: the next pose at the same offset, or, in poses(), once the next Posed is
asked for (its slot takes the next pose sent). Copy what you keep.
"""

import functools
import hashlib
import json
import mmap
import os
from time import monotonic_ns
from dataclasses import dataclass, field

import numpy as np
from sweepd.protocol import (BindOptions, Body, Bye, ClipFrame, ClipInfo, ContactSheet,
                             ContactSheetRequest, DeformMethod, Error,
                             ExrCompression, Features, Hello, ListModels, LoadModel, MapLayers,
                             MapSharedMemory, Mesh, MeshRequest, ModelInfo, ModelList, Pose,
                             PoseByName, PoseDelivery, PosedVertices, PoseFromClip,
                             PositionFormat, PositionMap, PositionMapRequest, SharedMemory, Stats,
                             StatsRequest, StreamSubscribed, SubscribeStream, UploadClip, Vec3,
                             Welcome)

from . import meshopt
from .connection import body_of, finish_frame, new_builder
from .errors import ConnectionLost, SweepdError, Timeout, UnknownModel, server_error

PROTOCOL_VERSION = (1, 16)  # a contact sheet's edge length ratios (1.16) are the newest it reads
METHODS = {"sweep": DeformMethod.DeformMethod.Sweep, "lbs": DeformMethod.DeformMethod.Lbs,
           "dqs": DeformMethod.DeformMethod.Dqs}
FEATURES = {"folding": Features.Features.Folding, "protrusion": Features.Features.Protrusion,
            "bulge": Features.Features.Bulge, "volume": Features.Features.Volume,
            "contact": Features.Features.Contact}
ENCODINGS = {"float32": PositionFormat.PositionFormat.Float32,
             "float16": PositionFormat.PositionFormat.Float16,
             "meshopt": PositionFormat.PositionFormat.Meshopt}
# BindOptions.orientation: the sweeps' orientation curve Q(t).
ORIENTATIONS = {"linear": 0, "smooth": 1}
LAYERS = {"position": MapLayers.MapLayers.Position, "normal": MapLayers.MapLayers.Normal,
          "coverage": MapLayers.MapLayers.Coverage}
COMPRESSIONS = {name.lower(): value for name, value in vars(ExrCompression.ExrCompression).items()
                if not name.startswith("_")}


@dataclass(frozen=True)
class ModelSummary:
    name: str
    model_id: int          # 0: in the server's model directory, not loaded yet
    content_id: str        # SHA-256 of what the binding was made from ("" when not loaded)
    vertex_count: int
    joint_count: int


@dataclass(frozen=True)
class MeshRange:
    """One mesh of a model made of several (protocol 1.6): positions[first_vertex:
    first_vertex + vertex_count] of every pose are this mesh's vertices."""
    name: str
    first_vertex: int
    vertex_count: int
    material: str
    first_triangle: int
    triangle_count: int
    rigid_joint: int              # -1: skinned; else the joint it follows rigidly
    swept: bool                   # bound to the body's sweeps (else its skin weights alone)
    mesh: int                     # which of the file's meshes it is a primitive of (0-based)


@dataclass(frozen=True)
class BindWarning:
    """A body region where the server's self-check of the binding (protocol 1.14, issue 47)
    found the sweep still worse than skinning on the model's range of motion."""
    region: str                   # "left arm", "neck", ...
    worse_poses: int              # of Model.self_check_poses
    sweep_stretch: float          # at the worst pose, the sweep's largest edge length ratio
    baseline_stretch: float       # the better baseline's there (both 0: flipped triangles alone)
    baseline: str                 # "LBS" or "DQS" ("" with sweep_stretch 0)
    pose: str                     # that pose's range-of-motion move, e.g. "elbow flexion 150°"
    extra_flipped: int            # most triangles flipped beyond the baseline's in one pose
    flipped_pose: str             # that move ("" when never)
    text: str                     # the whole warning, as `sweepctl bind` prints it


@dataclass(frozen=True)
class Model:
    model_id: int
    name: str
    content_id: str
    joint_names: list
    joint_parents: list
    vertex_count: int
    triangle_count: int
    rig_convention: str
    meshes: list = ()             # MeshRange per mesh, in vertex order (empty before 1.6)
    self_check_poses: int = 0     # poses the binding's self-check judged (0: before 1.14)
    bind_warnings: list = ()      # BindWarning per region still worse than skinning (1.14)


@dataclass(frozen=True)
class Clip:
    clip_id: str                  # SHA-256 of the BVH text and scale (or glTF bytes, animation)
    name: str
    frame_count: int
    frames_per_second: float
    joint_count: int
    warnings: list                # what did not stop the server reading the clip, then (1.12,
                                  # upload_clip(model=)) "on model 'NAME': ..." naming the clip
                                  # joints that drive no model joint and the model joints the
                                  # clip leaves without motion


@dataclass(frozen=True)
class Sheet:
    """A contact sheet drawn by the server (contact_sheet()): the PNG file's bytes, its size,
    each cell's shortest and longest edge as length ratios l / l_rest, arrays (frames, methods),
    and the GL renderer."""
    png: bytes
    width: int
    height: int
    shortest_edge_ratio: np.ndarray
    longest_edge_ratio: np.ndarray
    renderer: str


@dataclass(frozen=True)
class _Output:
    method: str
    features: tuple
    encoding: str
    normals: bool


@dataclass
class Posed:
    positions: np.ndarray         # (vertices, 3) float32
    normals: np.ndarray | None    # (vertices, 3) float32 when asked for
    sequence: int
    client_time_ns: int           # when this client sent the pose (time.monotonic_ns())
    dropped_before: int           # latest_wins: poses the server dropped since the last reply
    timings_ns: dict = field(default_factory=dict)  # queued, deform, features, encode


@dataclass
class RestMesh:
    positions: np.ndarray         # (vertices, 3) float32
    triangles: np.ndarray         # (triangles, 3) uint32
    uvs: np.ndarray | None        # (vertices, 2) float32, None without UVs
    skin_joints: np.ndarray       # (vertices, 4) uint16
    skin_weights: np.ndarray      # (vertices, 4) float32


def _text(value):
    return value.decode() if value is not None else ""


def _bind_warning(warning):
    return BindWarning(_text(warning.Region()), warning.WorsePoses(), warning.SweepStretch(),
                       warning.BaselineStretch(), _text(warning.Baseline()), _text(warning.Pose()),
                       warning.ExtraFlipped(), _text(warning.FlippedPose()), _text(warning.Text()))


def _mesh_range(mesh):
    return MeshRange(_text(mesh.Name()), mesh.FirstVertex(), mesh.VertexCount(),
                     _text(mesh.Material()), mesh.FirstTriangle(), mesh.TriangleCount(),
                     mesh.RigidJoint(), mesh.Swept(), mesh.Mesh())


@dataclass(frozen=True)
class Send:
    """A step of an exchange: send this frame (bytes, length prefix included)."""
    frame: bytes


@dataclass(frozen=True)
class Receive:
    """A step of an exchange: the next reply, which must be a `table` (a generated class)."""
    table: type


@dataclass(frozen=True)
class ReceiveDescriptor:
    """A step of an exchange: the next reply as a `table`, with the file descriptor its frame's
    first bytes carry (SCM_RIGHTS, on a Unix socket): answered with (body, descriptor or
    None); the exchange owns the descriptor."""
    table: type


class Exchanges:
    """The requests of a sweepd session as exchanges, and what the session knows: the models
    and clips loaded on it, its pose sequence. Client and AsyncClient run them."""

    # (SHA-256 of the .glb, name) → the content id a server gave it: shared by every client
    # of the process, so a reconnect or another replica is asked by id before bytes are sent.
    _uploaded = {}
    # clip id → (BVH text, name, length scale) of every clip this process uploaded.
    _clip_sources = {}
    # content id → (name, .glb bytes or None for a model loaded by name, orientation curve) of
    # every model this process loaded: a Model used on a server that lacks it gets it again.
    _model_sources = {}
    # Whether the client can answer a ReceiveDescriptor (map_shared_memory).
    receives_descriptors = True

    def __init__(self, host="127.0.0.1", port=7878, token="", *, unix=None, tls=None,
                 timeout=30.0, client_name="sweepd-client", latest_wins=False,
                 allow_plaintext=False):
        """tls: an ssl.SSLContext (ssl.create_default_context(cafile=...)) for a TLS listener.
        A token is not sent over plain TCP to a host that is not loopback unless
        allow_plaintext. Every receive waits at most `timeout` seconds."""
        self._endpoint = (host, port, unix, tls, timeout)
        self._greeting = (token, client_name, latest_wins, allow_plaintext)
        self._models = {}
        self._clips = set()  # clip ids uploaded on this connection
        self._sequence = 0
        self._region = None  # mmap of the shared region (map_shared_memory)
        self.server_version = (0, 0)
        self.max_poses_in_flight = 1

    # -- requests -------------------------------------------------------------------------

    def _list_models(self):
        """The models the server holds, then those in its model directory."""
        builder = new_builder(64)
        ListModels.Start(builder)
        yield Send(finish_frame(builder, Body.Body.ListModels, ListModels.End(builder)))
        reply = yield Receive(ModelList.ModelList)
        return [ModelSummary(_text(m.Name()), m.ModelId(), _text(m.ContentId()), m.VertexCount(),
                             m.JointCount())
                for m in (reply.Models(i) for i in range(reply.ModelsLength()))]

    def _load(self, name):
        """A model the server holds or finds in its store or model directory, by name."""
        model = yield from self._load_model(name, b"")
        if model.content_id:
            Exchanges._model_sources.setdefault(model.content_id, (name, None, 0))
        return model

    def _upload(self, glb, name=None, orientation="linear"):
        """Uploads a .glb (a path or its bytes) and returns the bound Model, named `name`, else
        the file's base name ("body" for dir/body.glb; "upload" for bytes); Model.name is the
        name the server holds it under (a server that held these bytes already keeps the name
        it gave them). orientation: the
        sweeps' orientation curve, "linear" (the paper's) or "smooth" (C2). Bytes this process
        uploaded before (on any client) are named by their content id first, without sending
        them: a server that holds the model, or shares a store with one that does, answers at
        once; one that answers UnknownModel gets the bytes (as client/model_source.h does)."""
        if not isinstance(glb, (bytes, bytearray, memoryview)):
            path = os.fspath(glb)
            with open(path, "rb") as file:
                glb = file.read()
            # The file's base name, never the local path: every client and every restart finds
            # the model by the same name (as client/model_source.h names it).
            name = name or os.path.splitext(os.path.basename(path))[0]
        name, glb = name or "upload", bytes(glb)
        curve = _choice(ORIENTATIONS, orientation, "orientation")
        key = (hashlib.sha256(glb).digest(), name, curve)
        content_id = Exchanges._uploaded.get(key)
        if content_id:
            try:
                return (yield from self._load_model(name, b"", content_id=content_id))
            except UnknownModel:
                pass  # a server with a store of its own: send the bytes
        model = yield from self._load_model(name, glb, orientation=curve)
        if model.content_id:
            Exchanges._uploaded[key] = model.content_id
            Exchanges._model_sources[model.content_id] = (name, glb, curve)
        return model

    def _present(self, model):
        """A Model from another connection made present on this one before a request names it:
        asked for by its content id (answered at once by a server that holds it or shares a
        store with one that does); a server that answers UnknownModel (a replica with a store
        of its own, a daemon restarted on an empty store) gets the bytes this process uploaded
        again, or the name it was loaded by (as client/model_source.h does)."""
        source = Exchanges._model_sources.get(model.content_id)
        if model.content_id:
            try:
                return (yield from self._load_model(model.name, b"", content_id=model.content_id))
            except UnknownModel:
                if source is None:
                    raise
        name, glb, curve = source or (model.name, None, 0)
        return (yield from self._load_model(name, glb or b"", orientation=curve))

    def _mesh(self, model):
        """The model's rest mesh (in the order of every Posed's vertices)."""
        model_id = yield from self._model_id(model)
        builder = new_builder(64)
        MeshRequest.Start(builder)
        MeshRequest.AddModelId(builder, model_id)
        yield Send(finish_frame(builder, Body.Body.MeshRequest, MeshRequest.End(builder)))
        reply = yield Receive(Mesh.Mesh)
        uvs = None if reply.UvsIsNone() or reply.UvsLength() == 0 else \
            reply.UvsAsNumpy().reshape(-1, 2)
        return RestMesh(reply.RestPositionsAsNumpy().reshape(-1, 3),
                        reply.IndicesAsNumpy().reshape(-1, 3), uvs,
                        reply.SkinJointsAsNumpy().reshape(-1, 4),
                        reply.SkinWeightsAsNumpy().reshape(-1, 4))

    def _upload_clip(self, clip=None, name=None, length_scale=1.0, joint_name_map=None, *,
                     animation=None, own_skeleton=False, model=None, range_of_motion=False):
        """Keeps a clip on the server and returns its Clip: a BVH clip (a path, or the BVH text
        itself), or (protocol 1.7) an animation of a glTF file (a .glb/.gltf path, or the file's
        bytes; self-contained: the server reads only the GLB chunk and data: URIs), or (1.8) an
        animation stack of an FBX or COLLADA file (a .fbx/.dae path, or its bytes).
        length_scale multiplies a BVH's lengths (CMU's inches to metres: 0.056444; glTF is in
        metres). joint_name_map: {clip joint: model joint or None} where names and rig roles do
        not say (as `sweepctl --bvh-map`; protocol 1.5). The server retargets the clip onto each
        model it poses (as `sweepctl pose --bvh` / `--clip-from` do). A glTF clip's `animation`
        is its name or index (None: the first); own_skeleton=True plays it on the joints of the
        model whose file it came from, as they are (as `sweepctl pose MODEL.glb --clip`): a
        model with other joints is an InvalidArgument when posed. model (a Model, or a name
        loaded on this connection; protocol 1.12): the model the clip will play on; the Clip's
        warnings then also name what playing it there leaves unmapped (clip joints that drive
        no model joint, model joints left without motion), as `sweepctl pose` prints them.
        range_of_motion=True (protocol 1.13), with model and no clip: the model's range of
        motion, built by the server from its skeleton and rig map (1441 frames at 30 fps for a
        full rig; `sweepctl rom` writes the same clip), played on the model's own joints."""
        if range_of_motion:
            return (yield from self._upload_range_of_motion(
                model, clip=clip, name=name, length_scale=length_scale,
                joint_name_map=joint_name_map, animation=animation, own_skeleton=own_skeleton))
        if clip is None:
            raise ValueError("upload_clip: a clip (a path, BVH text or a file's bytes), or "
                             "range_of_motion=True with model=")
        model_id = None if model is None else (yield from self._model_id(model))
        gltf = None
        if isinstance(clip, (bytes, bytearray, memoryview)):
            gltf = bytes(clip)
        elif isinstance(clip, os.PathLike) or "\n" not in clip:
            path = os.fspath(clip)
            name = name or os.path.basename(path)
            if path.lower().endswith((".glb", ".gltf", ".fbx", ".dae")):
                with open(path, "rb") as file:
                    gltf = file.read()
            else:
                with open(path, encoding="utf-8") as file:
                    clip = file.read()
        if gltf is None and (animation is not None or own_skeleton):
            raise ValueError("animation and own_skeleton choose an animation of a glTF, FBX or "
                             "COLLADA file (its path or its bytes), not of a BVH clip")
        builder = new_builder(1024 + len(gltf if gltf is not None else clip))
        source = builder.CreateByteVector(gltf) if gltf is not None else builder.CreateString(clip)
        label = builder.CreateString(name or ("clip.glb" if gltf is not None else "clip.bvh"))
        name_map = (builder.CreateString(json.dumps(joint_name_map)) if joint_name_map
                    else None)
        chosen = builder.CreateString(str(animation)) if animation is not None else None
        UploadClip.Start(builder)
        UploadClip.AddName(builder, label)
        if gltf is None:
            UploadClip.AddBvh(builder, source)
            UploadClip.AddLengthScale(builder, length_scale)
        else:
            UploadClip.AddGltf(builder, source)
            if chosen is not None:
                UploadClip.AddAnimation(builder, chosen)
            UploadClip.AddOwnSkeleton(builder, own_skeleton)
        if name_map is not None:
            UploadClip.AddJointNameMap(builder, name_map)
        if model_id is not None:
            UploadClip.AddModelId(builder, model_id)
        yield Send(finish_frame(builder, Body.Body.UploadClip, UploadClip.End(builder)))
        return (yield from self._held_clip(dict(
            clip=gltf if gltf is not None else clip, name=name, length_scale=length_scale,
            joint_name_map=joint_name_map, animation=animation, own_skeleton=own_skeleton)))

    def _upload_range_of_motion(self, model, **others):
        """upload_clip(range_of_motion=True, model=...): nothing else of a clip may be given."""
        given = [key for key, value in others.items()
                 if value not in (None, False) and not (key == "length_scale" and value == 1.0)]
        if given:
            raise ValueError("upload_clip(range_of_motion=True): the server builds the clip from "
                             "the model; do not pass " + ", ".join(given))
        if model is None:
            raise ValueError("upload_clip(range_of_motion=True) needs model=: the model whose "
                             "range of motion it is")
        model_id = yield from self._model_id(model)
        builder = new_builder(64)
        UploadClip.Start(builder)
        UploadClip.AddModelId(builder, model_id)
        UploadClip.AddRangeOfMotion(builder, True)
        yield Send(finish_frame(builder, Body.Body.UploadClip, UploadClip.End(builder)))
        # Sent again, to a server that lacks it, for the model as loaded here.
        return (yield from self._held_clip(dict(range_of_motion=True,
                                                model=self._models[model_id])))

    def _held_clip(self, source):
        """The ClipInfo answering an UploadClip, as a Clip; `source`: the upload_clip arguments
        that send it again (_clip_id)."""
        info = yield Receive(ClipInfo.ClipInfo)
        result = Clip(_text(info.ClipId()), _text(info.Name()), info.FrameCount(),
                      info.FramesPerSecond(), info.JointCount(),
                      [_text(info.Warnings(i)) for i in range(info.WarningsLength())])
        self._clips.add(result.clip_id)
        Exchanges._clip_sources[result.clip_id] = source
        return result

    def _pose(self, model, rotations=None, root=None, *, clip=None, frame=None, time=None,
              loop=False, fps=0.0, method="sweep", features=(), float16=False, normals=False,
              encoding=None, shared_offset=None):
        """One pose → Posed: `rotations` (None: the rest pose) and `root` (the root joint's
        translation, None: at rest); or, with clip=, the clip's `frame` (an index) or `time`
        (seconds; `fps` overrides the clip's rate, `loop` wraps past its end). shared_offset:
        the reply written into the shared region at that byte (map_shared_memory)."""
        model_id = yield from self._model_id(model)
        output = _output(method, features, float16, encoding, normals)
        clip_id = (yield from self._clip_id(clip)) if clip is not None else None
        point = (rotations, root) if clip is None else _clip_point(frame, time)
        if shared_offset is not None:
            self._require_region()
        yield self._pose_request(model_id, output, clip_id, point, loop, fps, shared_offset)
        return _posed((yield Receive(PosedVertices.PosedVertices)), self._region, output.normals)

    def _poses(self, model, frames, *, clip=None, loop=False, fps=0.0, method="sweep",
               features=(), float16=False, normals=False, window=None, encoding=None,
               shared=False):
        """Streams `frames` with up to `window` poses in flight (default: the server's
        max_poses_in_flight) and yields each Posed in order (with latest_wins, the answered
        ones: Posed.dropped_before counts the others). `frames`: rotations, or
        (rotations, root) pairs; with clip=, frame indices (int) or times in seconds (float).
        shared: the replies written into the shared region, one slot per pose in flight (the
        window is at most the slots the region holds)."""
        model_id = yield from self._model_id(model)
        output = _output(method, features, float16, encoding, normals)
        clip_id = (yield from self._clip_id(clip)) if clip is not None else None
        window = window or self.max_poses_in_flight
        slot = 0
        if shared:
            self._require_region()
            slot = self._models[model_id].vertex_count * 3 * 4 * (2 if normals else 1)
            slots = len(self._region) // slot
            if slots == 0:
                raise SweepdError(f"the shared region of {len(self._region)} bytes holds no "
                                  f"reply of {slot} bytes")
            window = min(window, slots)
        frames, pending, sent = iter(frames), 0, 0
        while True:
            while pending < window:
                point = next(frames, None)
                if point is None:
                    break
                offset = sent % window * slot if shared else None
                yield self._pose_request(model_id, output, clip_id, point, loop, fps, offset)
                pending += 1
                sent += 1
            if pending == 0:
                return
            posed = _posed((yield Receive(PosedVertices.PosedVertices)), self._region,
                           output.normals)
            pending -= 1 + posed.dropped_before
            yield posed

    def _stream(self, stream, *, method="sweep", features=(), float16=False, normals=False,
                encoding=None):
        """Protocol 1.15: subscribes to a stream the server receives (a VMC stream, sweepd
        --vmc-listen; `stream` is its name, the model its receiver poses) and yields a Posed per
        frame of it, for as long as the caller iterates: Posed.sequence is the stream's frame
        number. Latest wins: the client must be made with
        latest_wins=True (the server refuses otherwise), and a caller slower than the stream gets
        its newest frame (Posed.dropped_before counts those it missed)."""
        output = _output(method, features, float16, encoding, normals)
        builder = new_builder(256)
        name = builder.CreateString(stream)
        pose = self._add_pose(builder, 0, output)
        SubscribeStream.Start(builder)
        SubscribeStream.AddStream(builder, name)
        SubscribeStream.AddPose(builder, pose)
        yield Send(finish_frame(builder, Body.Body.SubscribeStream, SubscribeStream.End(builder)))
        yield Receive(StreamSubscribed.StreamSubscribed)
        while True:
            yield _posed((yield Receive(PosedVertices.PosedVertices)), self._region,
                         output.normals)

    def _pose_by_name(self, model, rotations, root=None, *, method="sweep", features=(),
                      float16=False, normals=False, encoding=None):
        """One pose from {joint name: (x, y, z, w)}, in the model's joint names or any rig
        naming convention the server knows (Mixamo, Unreal, CMU, ...); joints not named keep
        their rest rotation. Unknown names raise errors.InvalidArgument naming them."""
        model_id = yield from self._model_id(model)
        builder = new_builder(256)
        names = [builder.CreateString(name) for name in rotations]
        PoseByName.StartJointNamesVector(builder, len(names))
        for name in reversed(names):
            builder.PrependUOffsetTRelative(name)
        name_vector = builder.EndVector()
        rotation_vector = _struct_vector(builder, _quaternions(list(rotations.values())), 4)
        pose = self._add_pose(builder, model_id,
                              _output(method, features, float16, encoding, normals), root=root)
        PoseByName.Start(builder)
        PoseByName.AddPose(builder, pose)
        PoseByName.AddJointNames(builder, name_vector)
        PoseByName.AddRotations(builder, rotation_vector)
        yield Send(finish_frame(builder, Body.Body.PoseByName, PoseByName.End(builder)))
        return _posed((yield Receive(PosedVertices.PosedVertices)))

    def _position_map(self, model, rotations=None, root=None, *, clip=None, frame=None,
                      time=None, loop=False, fps=0.0, width=1024, height=1024,
                      layers=("position",), compression="zip", half_normals=False,
                      method="sweep", features=()):
        """The posed surface rendered into UV space → the bytes of an OpenEXR file. The pose is
        given as for pose()."""
        model_id = yield from self._model_id(model)
        output = _Output(method, features, "float32", False)
        clip_id = (yield from self._clip_id(clip)) if clip is not None else None
        builder = new_builder(256)
        if clip_id is None:
            clip_frame = None
            pose = self._add_pose(builder, model_id, output, self._rotations(model_id, rotations),
                                  root)
        else:
            clip_frame = _add_clip_frame(builder, clip_id, _clip_point(frame, time), loop, fps)
            pose = self._add_pose(builder, model_id, output)
        PositionMapRequest.Start(builder)
        PositionMapRequest.AddPose(builder, pose)
        PositionMapRequest.AddWidth(builder, width)
        PositionMapRequest.AddHeight(builder, height)
        PositionMapRequest.AddCompression(builder, _choice(COMPRESSIONS, compression,
                                                           "compression"))
        PositionMapRequest.AddLayers(builder, _flags(LAYERS, layers, "layer"))
        PositionMapRequest.AddHalfNormals(builder, half_normals)
        if clip_frame is not None:
            PositionMapRequest.AddClip(builder, clip_frame)
        request = PositionMapRequest.End(builder)
        yield Send(finish_frame(builder, Body.Body.PositionMapRequest, request))
        return (yield Receive(PositionMap.PositionMap)).ExrAsNumpy().tobytes()

    def _contact_sheet(self, model, clip, frames, methods=("sweep", "lbs", "dqs"), *,
                       cell=(240, 320), focus="", heat=False, heat_scale=1.0, azimuth=0.0,
                       elevation=0.0):
        """Protocol 1.11: the server's contact sheet (`sweepctl sheet`'s grid: a row per clip
        frame, a column per method, captioned with the worst edge stretch) → Sheet. `clip` is an
        uploaded Clip (or its id); methods from sweep, sweep+volume, sweep+features,
        sweep+contact, lbs, dqs; cell=(width, height) pixels; focus a joint such as "elbow_l";
        heat colours the skin by stretch, red at heat_scale (1 = 100 %)."""
        model_id = yield from self._model_id(model)
        clip_id = yield from self._clip_id(clip)
        frames, methods = [int(f) for f in frames], [str(m) for m in methods]
        builder = new_builder(256)
        clip_text = builder.CreateString(clip_id)
        focus_text = builder.CreateString(focus)
        method_texts = [builder.CreateString(m) for m in methods]
        ContactSheetRequest.StartFramesVector(builder, len(frames))
        for f in reversed(frames):
            builder.PrependUint32(f)
        frame_vector = builder.EndVector()
        ContactSheetRequest.StartMethodsVector(builder, len(methods))
        for m in reversed(method_texts):
            builder.PrependUOffsetTRelative(m)
        method_vector = builder.EndVector()
        ContactSheetRequest.Start(builder)
        ContactSheetRequest.AddModelId(builder, model_id)
        ContactSheetRequest.AddClipId(builder, clip_text)
        ContactSheetRequest.AddFrames(builder, frame_vector)
        ContactSheetRequest.AddMethods(builder, method_vector)
        ContactSheetRequest.AddCellWidth(builder, int(cell[0]))
        ContactSheetRequest.AddCellHeight(builder, int(cell[1]))
        ContactSheetRequest.AddFocus(builder, focus_text)
        ContactSheetRequest.AddHeat(builder, bool(heat))
        ContactSheetRequest.AddHeatFullScale(builder, float(heat_scale))
        ContactSheetRequest.AddAzimuthDegrees(builder, float(azimuth))
        ContactSheetRequest.AddElevationDegrees(builder, float(elevation))
        request = ContactSheetRequest.End(builder)
        yield Send(finish_frame(builder, Body.Body.ContactSheetRequest, request))
        reply = yield Receive(ContactSheet.ContactSheet)
        cells = len(frames) * len(methods)
        ratios = []
        for figures in (reply.ShortestEdgeRatioAsNumpy(), reply.LongestEdgeRatioAsNumpy()):
            # A server before protocol 1.16 sends no ratios (flatbuffers gives 0 for none).
            figures = np.zeros(0, np.float32) if isinstance(figures, int) else figures.copy()
            if figures.size != cells:
                raise SweepdError(f"the server's contact sheet has {figures.size} cells' edge "
                                  f"length ratios for {cells} cells"
                                  + (" (a server before protocol 1.16 sends none)"
                                     if figures.size == 0 else ""))
            ratios.append(figures.reshape(len(frames), len(methods)))
        return Sheet(reply.PngAsNumpy().tobytes(), reply.Width(), reply.Height(), *ratios,
                     _text(reply.Renderer()))

    def _map_shared_memory(self, size):
        """Protocol 1.10, on a Unix socket: a region of `size` bytes shared with the server,
        which writes float32 pose replies into it (pose(shared_offset=), poses(shared=True));
        one region per connection, kept until it closes. Returns its size."""
        if not self.receives_descriptors:
            raise SweepdError(f"{type(self).__name__} cannot map shared memory: use the "
                              "blocking Client on sweepd's Unix socket")
        if self._region is not None:
            raise SweepdError("this connection has mapped its shared region already")
        size = int(size)
        builder = new_builder(64)
        MapSharedMemory.Start(builder)
        MapSharedMemory.AddBytes(builder, size)
        yield Send(finish_frame(builder, Body.Body.MapSharedMemory, MapSharedMemory.End(builder)))
        granted, descriptor = yield ReceiveDescriptor(SharedMemory.SharedMemory)
        try:
            if (granted.Bytes() != size or descriptor is None
                    or os.fstat(descriptor).st_size < size):
                raise ConnectionLost(f"the server answered MapSharedMemory without a region "
                                     f"of {size} bytes")
            self._region = mmap.mmap(descriptor, size, mmap.MAP_SHARED, mmap.PROT_READ)
        finally:
            if descriptor is not None:
                os.close(descriptor)  # the mapping keeps the region
        return size

    def _stats(self):
        """The server's Stats table (the generated class: .UptimeNs(), .Models(i), ...)."""
        builder = new_builder(64)
        StatsRequest.Start(builder)
        yield Send(finish_frame(builder, Body.Body.StatsRequest, StatsRequest.End(builder)))
        return (yield Receive(Stats.Stats))

    # -- the session's start and end ------------------------------------------------------

    def _hello(self, connection):
        """Hello → Welcome on `connection` (its address, tls and loopback say where it goes),
        with the constructor's token, client name and delivery."""
        token, client_name, latest_wins, allow_plaintext = self._greeting
        if token and not connection.tls and not connection.loopback and not allow_plaintext:
            raise SweepdError(f"{connection.address}: refusing to send the token over plain "
                              "TCP to a host that is not loopback; pass tls= or "
                              "allow_plaintext=True on a private network")
        builder = new_builder(256)
        token_offset = builder.CreateString(token)
        name = builder.CreateString(client_name)
        Hello.Start(builder)
        Hello.AddVersionMajor(builder, PROTOCOL_VERSION[0])
        Hello.AddVersionMinor(builder, PROTOCOL_VERSION[1])
        Hello.AddAuthToken(builder, token_offset)
        Hello.AddClientName(builder, name)
        Hello.AddDelivery(builder, PoseDelivery.PoseDelivery.LatestWins if latest_wins
                          else PoseDelivery.PoseDelivery.InOrder)
        yield Send(finish_frame(builder, Body.Body.Hello, Hello.End(builder)))
        try:
            welcome = yield Receive(Welcome.Welcome)
        except Timeout:
            raise
        except ConnectionLost as error:
            if connection.tls:
                raise
            # A TLS listener drops a plaintext Hello without a reply.
            raise ConnectionLost(f"{error} (closed before Welcome: if sweepd serves TLS, "
                                 "pass tls=)") from error
        self.server_version = (welcome.VersionMajor(), welcome.VersionMinor())
        self.max_poses_in_flight = max(1, welcome.MaxPosesInFlight())

    @staticmethod
    def _bye(reason):
        """The frame of a Bye (sent without waiting for a reply)."""
        builder = new_builder(64)
        text = builder.CreateString(reason)
        Bye.Start(builder)
        Bye.AddReason(builder, text)
        return finish_frame(builder, Body.Body.Bye, Bye.End(builder))

    # -- internals ------------------------------------------------------------------------

    def _load_model(self, name, glb, content_id="", orientation=0):
        builder = new_builder(1024 + len(glb))
        gltf = builder.CreateByteVector(glb) if glb else None
        name_offset = builder.CreateString(name)
        content_id_offset = builder.CreateString(content_id) if content_id else None
        options = None
        if orientation:
            BindOptions.Start(builder)
            BindOptions.AddOrientation(builder, orientation)
            options = BindOptions.End(builder)
        LoadModel.Start(builder)
        LoadModel.AddName(builder, name_offset)
        if options is not None:
            LoadModel.AddOptions(builder, options)
        if gltf is not None:
            LoadModel.AddGltf(builder, gltf)
        if content_id_offset is not None:
            LoadModel.AddContentId(builder, content_id_offset)
        yield Send(finish_frame(builder, Body.Body.LoadModel, LoadModel.End(builder)))
        info = yield Receive(ModelInfo.ModelInfo)
        bind = info.Bind()
        model = Model(info.ModelId(), _text(info.Name()), _text(info.ContentId()),
                      [_text(info.JointNames(j)) for j in range(info.JointNamesLength())],
                      [info.JointParents(j) for j in range(info.JointParentsLength())],
                      info.VertexCount(), info.TriangleCount(),
                      _text(bind.RigConvention()) if bind else "",
                      [_mesh_range(info.Meshes(k)) for k in range(info.MeshesLength())],
                      info.SelfCheckPoses(),
                      [_bind_warning(info.BindWarnings(k))
                       for k in range(info.BindWarningsLength())])
        self._models[model.name] = self._models[model.model_id] = model
        return model

    def _model_id(self, model):
        if isinstance(model, Model):
            if model.model_id not in self._models:  # loaded on another connection
                return (yield from self._present(model)).model_id
            return model.model_id
        if model not in self._models:
            if not isinstance(model, str):
                raise SweepdError(f"model {model}: not loaded on this connection (load or "
                                  "upload it first, or pass its name)")
            yield from self._load(model)
        return self._models[model].model_id

    def _rotations(self, model_id, rotations):
        """(joints, 4) little-endian float32 quaternions; None: every joint at rest."""
        if rotations is None:
            joints = len(self._models[model_id].joint_names)
            return np.tile(np.array([0.0, 0.0, 0.0, 1.0], "<f4"), (joints, 1))
        return _quaternions(rotations)

    def _require_region(self):
        if self._region is None:
            raise SweepdError("a reply in shared memory needs map_shared_memory() first")

    def _pose_request(self, model_id, output, clip_id, point, loop, fps, shared_offset=None):
        """The Send of one pose: `point` is rotations or (rotations, root) without a clip,
        a clip's frame index (int) or time in seconds (float) with one; shared_offset: the
        reply goes into the shared region there."""
        builder = new_builder(256)
        if clip_id is None:
            rotations, root = point if isinstance(point, tuple) else (point, None)
            pose = self._add_pose(builder, model_id, output,
                                  self._rotations(model_id, rotations), root, shared_offset)
            return Send(finish_frame(builder, Body.Body.Pose, pose))
        clip_frame = _add_clip_frame(builder, clip_id, point, loop, fps)
        pose = self._add_pose(builder, model_id, output, shared_offset=shared_offset)
        PoseFromClip.Start(builder)
        PoseFromClip.AddPose(builder, pose)
        PoseFromClip.AddClip(builder, clip_frame)
        return Send(finish_frame(builder, Body.Body.PoseFromClip, PoseFromClip.End(builder)))

    def _add_pose(self, builder, model_id, output, rotations=None, root=None, shared_offset=None):
        """A Pose table; without rotations for a clip frame or named joints."""
        rotation_vector = None if rotations is None else _struct_vector(builder, rotations, 4)
        self._sequence += 1
        Pose.Start(builder)
        Pose.AddModelId(builder, model_id)
        Pose.AddSequence(builder, self._sequence)
        Pose.AddClientTimeNs(builder, monotonic_ns())
        if rotation_vector is not None:
            Pose.AddRotations(builder, rotation_vector)
        if root is not None:
            Pose.AddRootTranslation(builder, Vec3.CreateVec3(builder, *map(float, root)))
        Pose.AddMethod(builder, _choice(METHODS, output.method, "method"))
        Pose.AddFeatures(builder, _flags(FEATURES, output.features, "feature"))
        Pose.AddPositions(builder, ENCODINGS[output.encoding])
        Pose.AddNormals(builder, output.normals)
        if shared_offset is not None:
            Pose.AddIntoSharedMemory(builder, True)
            Pose.AddSharedOffset(builder, shared_offset)
        return Pose.End(builder)

    def _clip_id(self, clip):
        """The clip's id, uploaded first to this connection's server when another client of the
        process uploaded it (the server keeps clips in memory only: a restart or another
        replica lacks them; the same text gives the same id)."""
        clip_id = clip.clip_id if isinstance(clip, Clip) else str(clip)
        if clip_id not in self._clips and clip_id in Exchanges._clip_sources:
            yield from self._upload_clip(**Exchanges._clip_sources[clip_id])
        return clip_id


class Run:
    """One exchange in progress, driven by a client: step(reply) or step(error=...) feeds it
    the answer to its last step and returns its next one (a Send, a Receive, or a Posed for
    the caller); None once it has returned, with its value in .result."""

    def __init__(self, exchange):
        self._exchange, self.result = exchange, None

    def step(self, reply=None, error=None):
        try:
            return self._exchange.send(reply) if error is None else self._exchange.throw(error)
        except StopIteration as done:
            self.result = done.value
            return None


def with_requests(request):
    """A client class decorator: one public method per request of Exchanges (models, load,
    upload, mesh, upload_clip, pose, pose_by_name, position_map, contact_sheet,
    map_shared_memory, stats),
    made by request(exchange), and poses and stream, which return the client's
    self._drive(Run(exchange)): a generator of Posed (an async one for AsyncClient)."""
    def install(cls):
        for name, exchange in (("models", Exchanges._list_models), ("load", Exchanges._load),
                               ("upload", Exchanges._upload), ("mesh", Exchanges._mesh),
                               ("upload_clip", Exchanges._upload_clip),
                               ("pose", Exchanges._pose),
                               ("pose_by_name", Exchanges._pose_by_name),
                               ("position_map", Exchanges._position_map),
                               ("contact_sheet", Exchanges._contact_sheet),
                               ("map_shared_memory", Exchanges._map_shared_memory),
                               ("stats", Exchanges._stats)):
            setattr(cls, name, request(exchange))

        @functools.wraps(Exchanges._poses)
        def poses(self, *args, **kwargs):
            return self._drive(Run(Exchanges._poses(self, *args, **kwargs)))
        cls.poses = poses

        @functools.wraps(Exchanges._stream)
        def stream(self, *args, **kwargs):
            return self._drive(Run(Exchanges._stream(self, *args, **kwargs)))
        cls.stream = stream
        return cls
    return install


def reply_body(message, table, address):
    """The body of a received Message as `table`; an Error reply raises its ServerError, any
    other table ConnectionLost."""
    if message.BodyType() == Body.Body.Error:
        error = body_of(message, Error.Error)
        raise server_error(error.Code(), _text(error.Message()), error.Fatal(), error.Sequence())
    expected = getattr(Body.Body, table.__name__)
    if message.BodyType() != expected:
        raise ConnectionLost(f"{address}: expected {table.__name__}, got body type "
                             f"{message.BodyType()}")
    return body_of(message, table)


def _shared_floats(reply, region, first):
    """Array `first` (0: positions, 1: normals) of a reply in shared memory: a read-only
    (vertices, 3) view of the region, the offset checked against it (it is the server's word)."""
    count = 3 * reply.VertexCount()
    start = reply.SharedOffset() + first * count * 4
    if region is None or reply.SharedOffset() % 4 or start + count * 4 > len(region):
        raise ConnectionLost(f"a reply in shared memory at offset {reply.SharedOffset()} "
                             f"outside this connection's region")
    return np.frombuffer(region, np.float32, count, start).reshape(-1, 3)


def _posed(reply, region=None, normals_asked=False):
    """A PosedVertices reply → Posed; one in shared memory is read from `region`, its normals
    (which the reply does not flag) when the pose asked for them."""
    if reply.InSharedMemory():
        positions = _shared_floats(reply, region, 0)
    elif not reply.PositionsF32IsNone():
        positions = reply.PositionsF32AsNumpy().reshape(-1, 3)
    elif not reply.PositionsF16IsNone():
        positions = _from_half(reply.PositionsF16AsNumpy())
    elif not reply.PositionsMeshoptIsNone():
        origin = reply.PositionOrigin()
        positions = meshopt.decode_positions(
            reply.PositionsMeshoptAsNumpy(), reply.VertexCount(),
            (origin.X(), origin.Y(), origin.Z()), reply.PositionStep())
    else:
        positions = np.zeros((0, 3), np.float32)
    normals = None
    if reply.InSharedMemory():
        normals = _shared_floats(reply, region, 1) if normals_asked else None
    elif not reply.NormalsF32IsNone():
        normals = reply.NormalsF32AsNumpy().reshape(-1, 3)
    elif not reply.NormalsF16IsNone():
        normals = _from_half(reply.NormalsF16AsNumpy())
    elif not reply.NormalsMeshoptIsNone():
        normals = meshopt.decode_normals(reply.NormalsMeshoptAsNumpy(), reply.VertexCount())
    if len(positions) != reply.VertexCount():
        raise ConnectionLost(f"a reply with {len(positions)} positions for "
                             f"{reply.VertexCount()} vertices")
    t = reply.Timings()
    timings = {} if t is None else {"queued": t.QueuedNs(), "deform": t.DeformNs(),
                                    "features": t.FeaturesNs(), "encode": t.EncodeNs()}
    return Posed(positions, normals, reply.Sequence(), reply.ClientTimeNs(),
                 reply.DroppedBefore(), timings)


def _quaternions(rotations):
    rotations = np.ascontiguousarray(rotations, "<f4")
    if rotations.ndim != 2 or rotations.shape[1] != 4:
        raise SweepdError(f"rotations: shape {rotations.shape}, expected (joints, 4) "
                          "quaternions x, y, z, w")
    return rotations


def _clip_point(frame, time):
    """A clip pose's frame index (int) or time in seconds (float): exactly one is given."""
    if (frame is None) == (time is None):
        raise SweepdError("a clip pose takes one of frame= and time=")
    return frame if time is None else float(time)


def _add_clip_frame(builder, clip_id, frame, loop, fps):
    """A ClipFrame: `frame` an index (int) or a time in seconds (float)."""
    clip_id = builder.CreateString(clip_id)
    ClipFrame.Start(builder)
    ClipFrame.AddClipId(builder, clip_id)
    if isinstance(frame, float):
        ClipFrame.AddTimeSeconds(builder, frame)
    else:
        ClipFrame.AddFrame(builder, int(frame))
    ClipFrame.AddLoop(builder, loop)
    ClipFrame.AddFramesPerSecond(builder, fps)
    return ClipFrame.End(builder)


def _struct_vector(builder, rows, alignment):
    """A vector of structs (one per row: Quat is 4 little-endian floats) written in one copy, as
    flatbuffers' own CreateNumpyVector does for scalars: a struct per Prepend costs about 1 ms
    a pose for a 70-joint skeleton in pure Python."""
    size = rows.nbytes
    builder.StartVector(rows.shape[1] * rows.itemsize, len(rows), alignment)
    builder.head = builder.Head() - size
    builder.Bytes[builder.Head():builder.Head() + size] = rows.tobytes()
    return builder.EndVector()


def _output(method, features, float16, encoding, normals):
    """What a pose asks for; float16=True is encoding="float16". A meshopt decoder must be
    at hand before the request is sent (meshopt.MeshoptUnavailable otherwise)."""
    if float16 and encoding not in (None, "float16"):
        raise SweepdError(f"float16=True and encoding='{encoding}' disagree: pass one")
    encoding = encoding or ("float16" if float16 else "float32")
    _choice(ENCODINGS, encoding, "encoding")
    if encoding == "meshopt":
        meshopt.require()
    return _Output(method, features, encoding, normals)


def _from_half(bits):
    """binary16 bit patterns (uint16) → (n, 3) float32."""
    return bits.view(np.float16).astype(np.float32).reshape(-1, 3)


def _choice(options, name, what):
    if name not in options:
        raise SweepdError(f"unknown {what} '{name}' (one of {', '.join(options)})")
    return options[name]


def _flags(options, names, what):
    value = 0
    for name in names:
        value |= _choice(options, name, what)
    return value
