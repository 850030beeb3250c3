"""Drives a sweepd with the installed sweepd_client package only (run by
tests/server/python_package_test.cpp from a fresh venv, outside the source tree).

  python_package_check.py PORT TOKEN BODY.glb ROTATIONS.f32 OUT_DIR OTHER_PORT CLIP.bvh
                          ANIMATED.glb UNIX_SOCKET VMC_PORT

Uploads BODY.glb (also with the smooth orientation curve), poses it with ROTATIONS (float32 x, y, z, w per joint) and writes
OUT_DIR/positions.f32, OUT_DIR/map.exr and (protocol 1.14) the binding's self-check warnings,
OUT_DIR/bind_warnings.txt, for the test to compare with the library. Checks on
the way that streamed poses equal the single pose, that protocol errors raise their own
exception classes, that a silent server raises Timeout, and that bytes uploaded once are
named by content id afterwards: not sent again to PORT, sent to OTHER_PORT (a daemon with a
store of its own, which answers the content id with UnknownModel). Clips: a frame kept on the
server is the same by index, in a stream and by time; named joints pose like rotations; a
Clip uploaded on one server is uploaded again by the package on the other; a clip uploaded for a
model (protocol 1.12) names the joints it leaves unmapped there; a model's range of motion
(1.13) is asked for without clip bytes, and again on the other server; an upload without a name is
named by its file's base name, and UnknownModel names the models held. ANIMATED.glb is BODY
with three animations of its own joints ("linear", "step", "cubic", the same keys; protocol
1.7): uploaded as a clip by name and by index, played on its own joints (at a key every
interpolation gives the same pose) or retargeted onto BODY; an unknown name raises
ClipLoadFailed listing the file's animations. The meshopt
encoding decodes within half its 0.18 mm grid step. AsyncClient (asyncio) streams the same
poses and clip frames as the blocking Client, bit for bit, and raises the same exceptions.
On UNIX_SOCKET (the same daemon's) replies in shared memory (protocol 1.10) equal the TCP
replies bit for bit, single, streamed and clip frames, and the refusals are named. A contact
sheet (protocol 1.11) of a close-up with the heat map is written as OUT_DIR/sheet.png.
A VMC stream (protocol 1.15: the daemon's --vmc-listen on VMC_PORT, sent by liblo-tools'
oscsend) is subscribed to with stream(): its frame of one Bone/Pos equals pose_by_name of the
same rotation mirrored from Unity's frame, and stream() without latest_wins is refused.
Prints "ok" and exits 0, or names the failed check and exits 1.
"""

import asyncio
import os
import socket
import subprocess
import sys
import threading

import numpy as np
import sweepd_client
from sweepd_client import AsyncClient, Client, errors


def check(condition, what):
    if not condition:
        print(f"check failed: {what}")
        sys.exit(1)


def expect_error(cls, call):
    try:
        call()
    except cls as error:
        return error
    check(False, f"{cls.__name__} was not raised")


async def expect_async_error(cls, call):
    try:
        await call()
    except cls as error:
        return error
    check(False, f"{cls.__name__} was not raised (AsyncClient)")


async def check_async_client(port, token, glb, rotations, clip_file, expected):
    """AsyncClient against what the blocking Client got: `expected` holds its replies."""
    async with AsyncClient("127.0.0.1", int(port), token=token, timeout=60,
                           client_name="async") as sweepd:
        check(any(m.name == "mannequin" for m in await sweepd.models()), "async: models")
        body = await sweepd.upload(glb, name="uploaded")
        check(body.content_id == expected["content_id"], "async: the same binding")
        streamed = [posed async for posed in sweepd.poses(body, [rotations] * 20)]
        check(len(streamed) == 20, "async: 20 streamed replies")
        check(all(np.array_equal(p.positions, expected["posed"].positions) for p in streamed),
              "async: streamed poses equal the blocking client's")
        single = await sweepd.pose(body, rotations, normals=True)
        check(np.array_equal(single.normals, expected["posed"].normals), "async: normals")
        compact = await sweepd.pose(body, rotations, encoding="meshopt", normals=True)
        check(np.array_equal(compact.positions, expected["compact"].positions) and
              np.array_equal(compact.normals, expected["compact"].normals),
              "async: meshopt decodes as the blocking client's")
        clip = await sweepd.upload_clip(clip_file, length_scale=0.056444)
        frames = [posed async for posed in sweepd.poses(body, [99, 100, 101], clip=clip)]
        check(all(np.array_equal(a.positions, b.positions)
                  for a, b in zip(frames, expected["clip_frames"], strict=True)),
              "async: streamed clip frames equal the blocking client's")
        error = await expect_async_error(errors.WrongJointCount,
                                         lambda: sweepd.pose(body, rotations[:3]))
        check(not error.fatal, "async: WrongJointCount is not fatal")
        await expect_async_error(errors.UnknownModel, lambda: sweepd.load("absent"))
        # The connection goes on after errors.
        check(np.array_equal((await sweepd.pose(body, rotations)).positions,
                             expected["posed"].positions), "async: a pose after errors")
    await expect_async_error(
        errors.AuthFailed, lambda: AsyncClient("127.0.0.1", int(port), token="wrong").connect())
    silent = socket.socket()
    silent.bind(("127.0.0.1", 0))
    silent.listen()
    await expect_async_error(
        errors.Timeout,
        lambda: AsyncClient("127.0.0.1", silent.getsockname()[1], timeout=0.5).connect())
    silent.close()


def check_shared_memory(unix_socket, port, token, body, rotations, posed, clip, clip_frames):
    """Protocol 1.10 on the Unix socket: replies written into a region shared with the server
    are the TCP replies bit for bit (the same float32 the server deformed, only not copied
    through the socket); refusals are named, and the session goes on."""
    with Client(unix=unix_socket, token=token, timeout=60) as local:
        expect_error(errors.SweepdError, lambda: local.pose(body, rotations, shared_offset=0))
        slot = body.vertex_count * 3 * 4
        check(local.map_shared_memory(4 * 2 * slot) == 8 * slot, "the region's size")
        shared = local.pose(body, rotations, normals=True, shared_offset=2 * slot)
        check(np.array_equal(shared.positions, posed.positions), "shared positions equal TCP's")
        check(np.array_equal(shared.normals, posed.normals), "shared normals equal TCP's")
        check(not shared.positions.flags.writeable, "a read-only view of the region")
        count = 0
        for streamed in local.poses(body, [rotations] * 20, shared=True):
            check(np.array_equal(streamed.positions, posed.positions), "a streamed shared pose")
            count += 1
        check(count == 20, "20 shared replies")
        frames = [p.positions.copy() for p in local.poses(body, [99, 100, 101], clip=clip,
                                                        shared=True)]
        check(all(np.array_equal(a, b.positions) for a, b in zip(frames, clip_frames)),
              "shared clip frames equal TCP's")
        expect_error(errors.InvalidArgument,
                     lambda: local.pose(body, rotations, shared_offset=8 * slot - 4))
        expect_error(errors.SweepdError, lambda: local.map_shared_memory(slot))
        check(np.array_equal(local.pose(body, rotations).positions, posed.positions),
              "a plain reply after the refusals")
    with Client("127.0.0.1", int(port), token=token) as tcp:
        expect_error(errors.NotAvailable, lambda: tcp.map_shared_memory(slot))


def check_vmc_stream(port, token, vmc_port):
    """A Bone/Pos of LeftUpperArm (Unity's frame), then T, sent until the subscriber has a frame:
    the mannequin's stream frame is its LeftArm turned by the mirrored rotation, the rest at rest:
    pose_by_name's pose. 0.6, 0.8 about z in Unity is -0.6, 0.8 in glTF (docs/vmc.md)."""
    got_frame = threading.Event()

    def send():
        for _ in range(100):
            if got_frame.is_set():
                return
            subprocess.run(["oscsend", "127.0.0.1", vmc_port, "/VMC/Ext/Bone/Pos", "sfffffff",
                            "LeftUpperArm", "0", "0", "0", "0", "0", "0.6", "0.8"], check=True)
            subprocess.run(["oscsend", "127.0.0.1", vmc_port, "/VMC/Ext/T", "f", "1"], check=True)
            got_frame.wait(0.2)

    sender = threading.Thread(target=send)
    sender.start()
    try:
        with Client("127.0.0.1", int(port), token=token, latest_wins=True, timeout=60) as sweepd:
            streamed = next(iter(sweepd.stream("mannequin")))
            got_frame.set()
            expected = sweepd.pose_by_name("mannequin", {"LeftArm": (0.0, 0.0, -0.6, 0.8)})
            check(np.abs(streamed.positions - expected.positions).max() <= 1e-5,
                  "the stream's frame is pose_by_name's pose")
            rest = sweepd.pose("mannequin")
            check(np.abs(streamed.positions - rest.positions).max() > 0.05, "the arm moved")
    finally:
        got_frame.set()
        sender.join()
    with Client("127.0.0.1", int(port), token=token) as sweepd:
        expect_error(errors.InvalidArgument, lambda: next(iter(sweepd.stream("mannequin"))))


def main(port, token, glb, rotations_file, out, other_port, clip_file, animated_file,
         unix_socket, vmc_port):
    check("site-packages" in sweepd_client.__file__, f"imported from {sweepd_client.__file__}")
    with Client("127.0.0.1", int(port), token=token, timeout=60) as sweepd:
        check(any(m.name == "mannequin" for m in sweepd.models()), "the default model is listed")
        body = sweepd.upload(glb, name="uploaded")
        rotations = np.fromfile(rotations_file, np.float32).reshape(-1, 4)
        check(len(rotations) == len(body.joint_names), "one rotation per joint")
        posed = sweepd.pose(body, rotations, normals=True)
        check(posed.positions.shape == (body.vertex_count, 3), "positions shape")
        # Protocol 1.6: one mesh, one range over every vertex, swept with the body.
        check([(m.first_vertex, m.vertex_count, m.rigid_joint, m.swept) for m in body.meshes]
              == [(0, body.vertex_count, -1, True)], "mesh ranges")
        check(posed.normals.shape == (body.vertex_count, 3), "normals shape")
        posed.positions.astype(np.float32).tofile(f"{out}/positions.f32")
        # Protocol 1.14: the binding's self-check, its poses and a BindWarning per region still
        # worse than skinning, whose text begins with its figures; the texts go to
        # OUT_DIR/bind_warnings.txt for the test to compare with the library's.
        check(body.self_check_poses > 0, f"the binding was checked: {body.self_check_poses}")
        for w in body.bind_warnings:
            check(isinstance(w, sweepd_client.BindWarning), f"a BindWarning: {w!r}")
            check(w.text.startswith(f"{w.region}: worse than skinning in {w.worse_poses} of "
                                    f"{body.self_check_poses} poses"), f"warning: {w.text}")
        with open(f"{out}/bind_warnings.txt", "w", encoding="utf-8") as texts:
            texts.writelines(f"{w.text}\n" for w in body.bind_warnings)

        smooth = sweepd.upload(glb, name="uploaded_smooth", orientation="smooth")
        check(smooth.content_id != body.content_id, "the smooth curve is another binding")
        check(not np.array_equal(sweepd.pose(smooth, rotations).positions, posed.positions),
              "the smooth curve poses differently")

        streamed = list(sweepd.poses(body, [rotations] * 20))
        check(len(streamed) == 20, "20 streamed replies")
        check(all(np.array_equal(p.positions, posed.positions) for p in streamed),
              "streamed poses equal the single pose")
        half = sweepd.pose(body, rotations, float16=True)
        # float16 keeps 11 significant bits: 2^-11 relative, under 1 mm on a 2 m body.
        check(np.abs(half.positions - posed.positions).max() < 1e-3, "float16 within 1 mm")
        # Meshopt through Debian's libmeshoptimizer.so.2d (ctypes): a 0.18 mm grid, so half a
        # step (0.09 mm) plus float32 rounding; the bound is 0.1 mm. Normals as int8:
        # half of 1/127 per component.
        compact = sweepd.pose(body, rotations, encoding="meshopt", normals=True)
        check(np.abs(compact.positions - posed.positions).max() <= 0.9e-4 + 1e-6,
              "meshopt within 0.09 mm")
        check(np.abs(compact.normals - posed.normals).max() <= 0.5 / 127 + 1e-6,
              "meshopt normals within 1/254")
        expect_error(errors.SweepdError, lambda: sweepd.pose(body, encoding="float64"))
        expect_error(errors.SweepdError,
                     lambda: sweepd.pose(body, float16=True, encoding="meshopt"))
        # Without meshoptimizer's library the package says what it needs, before sending.
        missing = subprocess.run(
            [sys.executable, "-c", "import sweepd_client.meshopt as m\n"
             "try:\n    m.require()\nexcept m.MeshoptUnavailable as e:\n    print(e)"],
            env={**os.environ, "SWEEPD_MESHOPTIMIZER": "/nonexistent/libmeshoptimizer.so"},
            capture_output=True, text=True, check=True).stdout
        check("libmeshoptimizer2d" in missing, f"MeshoptUnavailable names the package: {missing}")

        error = expect_error(errors.WrongJointCount, lambda: sweepd.pose(body, rotations[:3]))
        check(error.code == errors.WrongJointCount.code and not error.fatal, "WrongJointCount")
        unknown_model = expect_error(errors.UnknownModel, lambda: sweepd.load("absent"))
        check("this server holds " in str(unknown_model) and "'uploaded' (id " in
              str(unknown_model), f"UnknownModel names the held models: {unknown_model}")
        expect_error(errors.InvalidPose, lambda: sweepd.pose(body, np.full_like(rotations, np.nan)))
        expect_error(errors.SweepdError, lambda: sweepd.pose(body, method="blend"))

        names = {name: rotations[j] for j, name in enumerate(body.joint_names)}
        check(np.array_equal(sweepd.pose_by_name(body, names).positions,
                             sweepd.pose(body, rotations).positions),
              "pose_by_name with every joint equals pose")
        expect_error(errors.InvalidArgument,
                     lambda: sweepd.pose_by_name(body, {"no_such_joint": rotations[0]}))

        clip = sweepd.upload_clip(clip_file, length_scale=0.056444)
        check(clip.frame_count > 100 and clip.frames_per_second > 0, "clip info")
        check(sweepd.upload_clip(clip_file, length_scale=0.056444).clip_id == clip.clip_id,
              "the same clip, the same id")
        frame = sweepd.pose(body, clip=clip, frame=100)
        stream = list(sweepd.poses(body, [99, 100, 101], clip=clip))
        check(np.array_equal(stream[1].positions, frame.positions), "a streamed clip frame")
        check(not np.array_equal(stream[0].positions, frame.positions), "frames differ")
        timed = sweepd.pose(body, clip=clip, time=100 / clip.frames_per_second)
        # Between-frame sampling rounds: the time of frame 100 lands on it within 0.1 mm.
        check(np.abs(timed.positions - frame.positions).max() < 1e-4, "a clip time")
        expect_error(errors.InvalidArgument, lambda: sweepd.pose(body, clip=clip,
                                                                 frame=clip.frame_count))
        expect_error(errors.UnknownClip, lambda: sweepd.pose(body, clip="0" * 64, frame=0))
        # A joint name map travels with the clip (1.5): the left forearm unmapped, the elbow
        # stays at rest, so frame 100 moves differently (1 mm is far below the forearm's swing).
        mapped = sweepd.upload_clip(clip_file, length_scale=0.056444,
                                    joint_name_map={"LeftForeArm": None})
        check(mapped.clip_id != clip.clip_id, "the map is part of the clip's id")
        check(np.abs(sweepd.pose(body, clip=mapped, frame=100).positions
                     - frame.positions).max() > 1e-3, "the map changes the pose")
        # Protocol 1.12 (issue 48): a clip uploaded for a model names what it leaves unmapped
        # there: a joint no model has, under a misspelt name, and the model's joints left still.
        with open(clip_file, encoding="utf-8") as file:
            text = file.read()
        end_site = text.index("End Site", text.index("JOINT Head"))
        misspelt = (text[:end_site] + "JOINT HeadTpo\n{\nOFFSET 0 1.5 0\nCHANNELS 0\n"
                    "End Site\n{\nOFFSET 0 1 0\n}\n}\n" + text[end_site:])
        silent = sweepd.upload_clip(misspelt, name="misspelt.bvh", length_scale=0.056444)
        check(silent.warnings == [], f"no model, no retargeting warning: {silent.warnings}")
        told = sweepd.upload_clip(misspelt, name="misspelt.bvh", length_scale=0.056444,
                                  model=body)
        check("on model 'uploaded': clip joints that drive no model joint (1): HeadTpo; pair "
              "them in a joint name map to drive them" in told.warnings,
              f"the misspelt joint is named: {told.warnings}")
        check(any(w.startswith("on model 'uploaded': model joints the clip leaves without "
                               "motion") for w in told.warnings),
              f"the model joints left still are named: {told.warnings}")
        # Protocol 1.7: a glTF file's animations as clips.
        # Named by its file's base name, not the path it was read from (issue 48).
        animated = sweepd.upload(os.path.abspath(animated_file))
        check(animated.name == "animated", f"an upload's name is its file's: {animated.name}")
        linear = sweepd.upload_clip(animated_file, animation="linear", own_skeleton=True)
        check(linear.frame_count == 6 and linear.clip_id != clip.clip_id, "a glTF clip's info")
        with open(animated_file, "rb") as file:
            cubic = sweepd.upload_clip(file.read(), animation=2, own_skeleton=True)
        key = sweepd.pose(animated, clip=linear, frame=3).positions
        check(np.array_equal(key, sweepd.pose(animated, clip=cubic, frame=3).positions),
              "a key frame is the key whatever the interpolation")
        check(np.abs(key - sweepd.pose(animated).positions).max() > 0.05, "the key is a pose")
        retargeted = sweepd.upload_clip(animated_file, animation="cubic")
        check(retargeted.clip_id != cubic.clip_id, "own_skeleton is part of the clip's id")
        check(np.abs(sweepd.pose(body, clip=retargeted, frame=3).positions
                     - sweepd.pose(body).positions).max() > 0.05, "a retargeted glTF clip")
        unknown = expect_error(errors.ClipLoadFailed,
                               lambda: sweepd.upload_clip(animated_file, animation="walk"))
        check("0 'linear', 1 'step', 2 'cubic'" in str(unknown), f"names listed: {unknown}")
        expect_error(ValueError, lambda: sweepd.upload_clip(clip_file, animation="walk"))
        # Protocol 1.13: the model's range of motion, built by the server (no clip bytes).
        rom = sweepd.upload_clip(range_of_motion=True, model=body)
        check(rom.name == "range of motion" and rom.frame_count > 30 and
              (rom.frame_count - 1) % 30 == 0, f"a range of motion's info: {rom}")
        rom_peak = sweepd.pose(body, clip=rom, frame=15)  # the first move's peak
        check(np.abs(rom_peak.positions - sweepd.pose(body).positions).max() > 0.05,
              "the range of motion moves the body")
        expect_error(ValueError, lambda: sweepd.upload_clip(range_of_motion=True))
        expect_error(ValueError, lambda: sweepd.upload_clip(clip_file, range_of_motion=True,
                                                            model=body))

        check_shared_memory(unix_socket, port, token, body, rotations,
                            sweepd.pose(body, rotations, normals=True), clip, stream)

        clip_map = sweepd.position_map(body, clip=clip, frame=100, width=64, height=64)
        check(clip_map[:4] == b"\x76\x2f\x31\x01", "a clip frame's position map")
        # Protocol 1.11: the server's contact sheet, two frames by two methods of 64 x 96, of the
        # clip as `sweepctl sheet --bvh` plays it (length_scale 1: the retargeter scales it).
        sheet = sweepd.contact_sheet(body, sweepd.upload_clip(clip_file), [100, 300], ("sweep", "lbs"), cell=(64, 96),
                                     focus="elbow_l", heat=True)
        check(sheet.png[:8] == b"\x89PNG\r\n\x1a\n" and len(sheet.png) > 1000, "a sheet's PNG")
        check((sheet.width, sheet.height) == (128, 192), f"sheet size {sheet.width}x{sheet.height}")
        # Each cell's shortest and longest edge as length ratios l / l_rest: the longest within
        # the quality tests' 3x, the shortest not collapsed to a point.
        check(sheet.shortest_edge_ratio.shape == (2, 2) and sheet.longest_edge_ratio.shape == (2, 2)
              and np.all((sheet.longest_edge_ratio >= 1) & (sheet.longest_edge_ratio <= 3))
              and np.all((sheet.shortest_edge_ratio > 0) & (sheet.shortest_edge_ratio <= 1)),
              f"sheet edge ratios {sheet.shortest_edge_ratio} {sheet.longest_edge_ratio}")
        with open(f"{out}/sheet.png", "wb") as file:
            file.write(sheet.png)
        unknown_method = expect_error(errors.InvalidArgument, lambda: sweepd.contact_sheet(
            body, clip, [1], ("sweep", "blend")))
        check("unknown method 'blend'" in str(unknown_method), f"named: {unknown_method}")

        asyncio.run(check_async_client(port, token, glb, rotations, clip_file, {
            "content_id": body.content_id, "posed": posed, "compact": compact,
            "clip_frames": stream}))

        exr = sweepd.position_map(body, rotations, width=128, height=64)
        with open(f"{out}/map.exr", "wb") as file:
            file.write(exr)

    def bytes_in(sweepd, client_name):
        stats = sweepd.stats()
        connections = [stats.Connections(i) for i in range(stats.ConnectionsLength())]
        return next(c.BytesIn() for c in connections if c.ClientName().decode() == client_name)

    glb_bytes = len(open(glb, "rb").read())
    with Client("127.0.0.1", int(port), token=token, client_name="again") as sweepd:
        again = sweepd.upload(glb, name="uploaded")
        check(again.content_id == body.content_id, "the same content id again")
        check(bytes_in(sweepd, "again") < glb_bytes / 10, "the bytes are not sent again")
    with Client("127.0.0.1", int(other_port), token=token, client_name="other") as sweepd:
        # The Model of the first server, posed on a server with a store of its own (as a daemon
        # restarted on an empty store is): named by its content id, answered UnknownModel, the
        # bytes uploaded again, then posed as there, streamed poses and position maps too.
        check(np.array_equal(sweepd.pose(body, rotations).positions, posed.positions),
              "a Model posed on a server that lacked it")
        check(all(np.array_equal(p.positions, posed.positions)
                  for p in sweepd.poses(body, [rotations] * 3)), "streamed there too")
        check(bytes_in(sweepd, "other") > glb_bytes, "the other server got the bytes once")
        other = sweepd.upload(glb, name="uploaded")
        check(other.content_id == body.content_id, "the same content id on the other server")
        check(bytes_in(sweepd, "other") > glb_bytes, "the other server got the bytes")
        # The Clip came from the first server; the package uploads it here before use.
        check(np.array_equal(sweepd.pose(other, clip=clip, frame=100).positions, frame.positions),
              "the clip frame on the other server")
        check(np.array_equal(sweepd.pose(other, clip=rom, frame=15).positions,
                             rom_peak.positions), "the range of motion asked for there again")

    check_vmc_stream(port, token, vmc_port)
    expect_error(errors.AuthFailed, lambda: Client("127.0.0.1", int(port), token="wrong"))
    silent = socket.socket()
    silent.bind(("127.0.0.1", 0))
    silent.listen()
    expect_error(errors.Timeout, lambda: Client("127.0.0.1", silent.getsockname()[1], timeout=0.5))
    print("ok")


if __name__ == "__main__":
    main(*sys.argv[1:])
