"""Drives a sweepd with the installed sweepd_client package only (run by
tests/server/python_package_test.cpp from a fresh venv, outside the source tree).

  python_package_check.py PORT TOKEN BODY.glb ROTATIONS.f32 OUT_DIR

Uploads BODY.glb, poses it with ROTATIONS (float32 x, y, z, w per joint) and writes
OUT_DIR/positions.f32 and OUT_DIR/map.exr for the test to compare with the library. Checks on
the way that streamed poses equal the single pose, that protocol errors raise their own
exception classes and that a silent server raises Timeout. Prints "ok" and exits 0, or names
the failed check and exits 1.
"""

import socket
import sys

import numpy as np
import sweepd_client
from sweepd_client import Client, errors


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


def main(port, token, glb, rotations_file, out):
    check("site-packages" in sweepd_client.__file__, f"imported from {sweepd_client.__file__}")
    with Client("127.0.0.1", int(port), token=token, timeout=60) as sweepd:
        check(any(m.name == "mannequin" for m in sweepd.models()), "the default model is listed")
        body = sweepd.upload(glb, name="uploaded")
        rotations = np.fromfile(rotations_file, np.float32).reshape(-1, 4)
        check(len(rotations) == len(body.joint_names), "one rotation per joint")
        posed = sweepd.pose(body, rotations, normals=True)
        check(posed.positions.shape == (body.vertex_count, 3), "positions shape")
        check(posed.normals.shape == (body.vertex_count, 3), "normals shape")
        posed.positions.astype(np.float32).tofile(f"{out}/positions.f32")

        streamed = list(sweepd.poses(body, [rotations] * 20))
        check(len(streamed) == 20, "20 streamed replies")
        check(all(np.array_equal(p.positions, posed.positions) for p in streamed),
              "streamed poses equal the single pose")
        half = sweepd.pose(body, rotations, float16=True)
        # float16 keeps 11 significant bits: 2^-11 relative, under 1 mm on a 2 m body.
        check(np.abs(half.positions - posed.positions).max() < 1e-3, "float16 within 1 mm")

        error = expect_error(errors.WrongJointCount, lambda: sweepd.pose(body, rotations[:3]))
        check(error.code == errors.WrongJointCount.code and not error.fatal, "WrongJointCount")
        expect_error(errors.UnknownModel, lambda: sweepd.load("absent"))
        expect_error(errors.InvalidPose, lambda: sweepd.pose(body, np.full_like(rotations, np.nan)))
        expect_error(errors.SweepdError, lambda: sweepd.pose(body, method="blend"))

        exr = sweepd.position_map(body, rotations, width=128, height=64)
        with open(f"{out}/map.exr", "wb") as file:
            file.write(exr)

    expect_error(errors.AuthFailed, lambda: Client("127.0.0.1", int(port), token="wrong"))
    silent = socket.socket()
    silent.bind(("127.0.0.1", 0))
    silent.listen()
    expect_error(errors.Timeout, lambda: Client("127.0.0.1", silent.getsockname()[1], timeout=0.5))
    print("ok")


if __name__ == "__main__":
    main(*sys.argv[1:])
