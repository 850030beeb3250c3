#!/usr/bin/python3
"""stream_poses.py: streams a BVH clip to sweepd as poses, on the sweepd-client package.

  /usr/bin/python3 client_examples/stream_poses.py --bvh clip.bvh
      [--host 127.0.0.1] [--port 7878] [--unix SOCKET] [--token T | --token-file FILE]
      [--tls [--tls-ca CA.pem] [--tls-cert C.pem --tls-key K.pem]] [--allow-plaintext]
      [--model NAME | --model-file body.glb] [--bvh-scale 0.056444]
      [--frames N] [--first-frame F] [--flat-out] [--latest-wins] [--float16]

The clip goes to the server once; the server retargets it, so this client sends frame numbers:
at the clip's rate (one pose in flight) or --flat-out (max_poses_in_flight). It prints what the
C++ stream_poses prints. The package is used installed, or from client_examples/python.
Exit codes: 0 all answered; 1 a pose's Error; 2 bad arguments or input; 3 unreachable or
broken connection; 4 refused.
"""

import argparse
import os
import ssl
import sys
import time

try:
    from sweepd_client import Client, errors
except ImportError:
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "python"))
    from sweepd_client import Client, errors

CMU_TO_METRES = 0.056444
BAD_INPUT = (errors.ClipLoadFailed, errors.ModelLoadFailed, errors.InvalidArgument)


def arguments(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--bvh", required=True, help="the BVH clip")
    parser.add_argument("--bvh-scale", type=float, default=CMU_TO_METRES, help="metres a unit")
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--port", type=int, default=7878)
    parser.add_argument("--unix", help="a Unix socket path instead of TCP")
    token = parser.add_mutually_exclusive_group()
    token.add_argument("--token", default="")
    token.add_argument("--token-file", type=argparse.FileType(encoding="utf-8"), help="1st line")
    parser.add_argument("--tls", action="store_true")
    parser.add_argument("--tls-ca", help="CA certificates, PEM (implies --tls)")
    parser.add_argument("--tls-cert", help="client certificate, PEM (implies --tls)")
    parser.add_argument("--tls-key", help="its key, PEM")
    parser.add_argument("--allow-plaintext", action="store_true", help="token in clear")
    parser.add_argument("--model", help="the model's name (default: mannequin, or the file's)")
    parser.add_argument("--model-file", help="a .glb to upload")
    parser.add_argument("--frames", type=int, default=0, help="frames to send (0: to the end)")
    parser.add_argument("--first-frame", type=int, default=0)
    parser.add_argument("--flat-out", action="store_true", help="ignore the clip's frame rate")
    parser.add_argument("--latest-wins", action="store_true")
    parser.add_argument("--float16", action="store_true")
    options = parser.parse_args(argv)
    if bool(options.tls_cert) != bool(options.tls_key):
        parser.error("--tls-cert and --tls-key go together")
    if options.frames < 0 or options.first_frame < 0:
        parser.error("--frames and --first-frame must not be negative")
    if options.token_file:
        options.token = options.token_file.readline().rstrip("\n")
    return options


def tls_context(options):
    if not (options.tls or options.tls_ca or options.tls_cert):
        return None
    context = ssl.create_default_context(cafile=options.tls_ca)
    context.minimum_version = ssl.TLSVersion.TLSv1_2
    if options.tls_cert:
        context.load_cert_chain(options.tls_cert, options.tls_key)
    return context


def percentile(values, q):
    values = sorted(values)
    return values[int(q * (len(values) - 1))] if values else 0.0


def paced(frames, fps, flat_out):
    """The frame numbers, each released at its time in the clip unless flat out."""
    start = time.monotonic()
    for i, frame in enumerate(frames):
        if not flat_out:
            time.sleep(max(0.0, start + i / fps - time.monotonic()))
        yield frame


def run(options):
    with Client(options.host, options.port, options.token, unix=options.unix,
                tls=tls_context(options), latest_wins=options.latest_wins,
                client_name="stream_poses.py", allow_plaintext=options.allow_plaintext) as sweepd:
        model = (sweepd.upload(options.model_file, options.model) if options.model_file
                 else sweepd.load(options.model or "mannequin"))
        # Where the server's self-check found the sweep worse than skinning (protocol 1.14).
        for warning in model.bind_warnings:
            print(f"warning: model '{model.name}': {warning.text}", file=sys.stderr)
        # With the model (protocol 1.12), the warnings also name what the clip leaves unmapped.
        clip = sweepd.upload_clip(options.bvh, name=options.bvh, length_scale=options.bvh_scale,
                                  model=model)
        for warning in clip.warnings:
            print(f"warning: {options.bvh}: {warning}", file=sys.stderr)
        print(f"model '{model.name}' (id {model.model_id}): {model.vertex_count} vertices, "
              f"{len(model.joint_names)} joints; clip {clip.frame_count} frames")
        if options.first_frame >= clip.frame_count:
            raise errors.InvalidArgument(f"--first-frame {options.first_frame} is outside the "
                                         f"clip's {clip.frame_count} frames")
        frames = range(options.first_frame, min(clip.frame_count, options.first_frame + (
            options.frames or clip.frame_count)))
        latencies, answered, dropped, errors_seen = [], 0, 0, 0
        start = time.monotonic()
        stream = sweepd.poses(model, paced(frames, clip.frames_per_second, options.flat_out),
                              clip=clip, float16=options.float16,
                              window=None if options.flat_out else 1)
        while True:
            try:
                posed = next(stream)
            except StopIteration:
                break
            except errors.ServerError as error:
                if error.fatal:
                    raise
                errors_seen += 1  # the stream ends here: the rest of the window is not read
                print(f"error {error}", file=sys.stderr)
                break
            latencies.append((time.monotonic_ns() - posed.client_time_ns) * 1e-6)
            answered, dropped = answered + 1, dropped + posed.dropped_before
        seconds = time.monotonic() - start
        stats = sweepd.stats()
        deform_ms = next((stats.Models(m).DeformLatency().P50Ns() * 1e-6
                          for m in range(stats.ModelsLength())
                          if stats.Models(m).ModelId() == model.model_id), 0.0)
    print(f"poses: sent {len(frames)}, answered {answered}, dropped {dropped}, errors "
          f"{errors_seen} in {seconds:.2f} s ({answered / seconds:.0f}/s)")
    print("round trip ms: " + "  ".join(f"{name} {percentile(latencies, q):.3f}" for name, q in
                                        (("p50", 0.5), ("p90", 0.9), ("p99", 0.99), ("max", 1))))
    ratio = percentile(latencies, 0.5) / deform_ms if deform_ms > 0 else 0.0
    print(f"server deformation ms: p50 {deform_ms:.3f} (round trip p50 / deformation p50 = "
          f"{ratio:.2f})")
    return 0 if errors_seen == 0 else 1


def main(argv):
    try:
        return run(arguments(argv))
    except (OSError, *BAD_INPUT, errors.ConnectionLost, errors.SweepdError) as error:
        print(f"stream_poses.py: {error}", file=sys.stderr)
        exit_codes = ((BAD_INPUT + (OSError,), 2), (errors.ConnectionLost, 3), (Exception, 4))
        return next(code for kinds, code in exit_codes if isinstance(error, kinds))


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
