// The viewer's requests as sweepd frames, and replies read back: FlatBuffers code that flatc
// generates from protocol/sweepd.fbs at build time (imported as @sweepd/protocol), framed as
// protocol/README.md says: size-prefixed, identifier "SWPD", one frame per WebSocket message.
import * as flatbuffers from 'flatbuffers';
import * as pb from '@sweepd/protocol';

export { pb };

const kVersionMajor = 1;
const kVersionMinor = 4;

export const kMethods = {
  sweep: pb.DeformMethod.Sweep,
  lbs: pb.DeformMethod.Lbs,
  dqs: pb.DeformMethod.Dqs,
};

// One frame: `body(builder)` writes the body and returns [type, offset].
function frame(requestId, body) {
  const builder = new flatbuffers.Builder(1024);
  const [type, offset] = body(builder);
  const message = pb.Message.createMessage(builder, BigInt(requestId), type, offset);
  builder.finishSizePrefixed(message, 'SWPD');
  return builder.asUint8Array();
}

export function hello(requestId, token) {
  return frame(requestId, (b) => [pb.Body.Hello, pb.Hello.createHello(
      b, kVersionMajor, kVersionMinor, b.createString(token), b.createString('sweepd viewer'),
      pb.PoseDelivery.InOrder)]);
}

export function listModels(requestId) {
  return frame(requestId, (b) => {
    pb.ListModels.startListModels(b);
    return [pb.Body.ListModels, pb.ListModels.endListModels(b)];
  });
}

// A held model by name (no bytes): answered by its ModelInfo (joint names, rest rotations).
export function loadModel(requestId, name) {
  return frame(requestId, (b) => {
    const nameOffset = b.createString(name);
    pb.LoadModel.startLoadModel(b);
    pb.LoadModel.addName(b, nameOffset);
    return [pb.Body.LoadModel, pb.LoadModel.endLoadModel(b)];
  });
}

export function meshRequest(requestId, modelId) {
  return frame(requestId,
               (b) => [pb.Body.MeshRequest, pb.MeshRequest.createMeshRequest(b, modelId)]);
}

export function uploadClip(requestId, name, bvh, lengthScale) {
  return frame(requestId, (b) => [pb.Body.UploadClip, pb.UploadClip.createUploadClip(
      b, b.createString(name), b.createString(bvh), lengthScale)]);
}

// The pose fields both pose requests share: float16 positions, no normals (the page shades
// flat), no features.
function poseFields(b, pose) {
  pb.Pose.startPose(b);
  pb.Pose.addModelId(b, pose.modelId);
  pb.Pose.addSequence(b, BigInt(pose.sequence));
  pb.Pose.addMethod(b, kMethods[pose.method]);
  pb.Pose.addPositions(b, pb.PositionFormat.Float16);
  return pb.Pose.endPose(b);
}

// Frame `frame` of a held clip, wrapping past its end.
export function poseFromClip(requestId, pose, clipId, frameIndex) {
  return frame(requestId, (b) => {
    const clipIdOffset = b.createString(clipId);
    const poseOffset = poseFields(b, pose);
    // flatc 2.0.8's TypeScript writes an optional scalar only when it differs from 0: frame 0
    // would be absent (the server then finds neither frame nor time). Force it out.
    b.forceDefaults(true);
    const clip = pb.ClipFrame.createClipFrame(b, clipIdOffset, frameIndex, null, true, 0);
    b.forceDefaults(false);
    pb.PoseFromClip.startPoseFromClip(b);
    pb.PoseFromClip.addPose(b, poseOffset);
    pb.PoseFromClip.addClip(b, clip);
    return [pb.Body.PoseFromClip, pb.PoseFromClip.endPoseFromClip(b)];
  });
}

// Local rotations {x, y, z, w} keyed by joint name; the joints not named keep their rest.
export function poseByName(requestId, pose, names, rotations) {
  return frame(requestId, (b) => {
    const nameOffsets =
        pb.PoseByName.createJointNamesVector(b, names.map((name) => b.createString(name)));
    pb.PoseByName.startRotationsVector(b, rotations.length);
    for (let i = rotations.length - 1; i >= 0; --i) {
      const q = rotations[i];
      pb.Quat.createQuat(b, q.x, q.y, q.z, q.w);
    }
    const rotationOffsets = b.endVector();
    const poseOffset = poseFields(b, pose);
    return [pb.Body.PoseByName,
            pb.PoseByName.createPoseByName(b, poseOffset, nameOffsets, rotationOffsets)];
  });
}

// The Message of one received WebSocket message (an ArrayBuffer): length prefix, root offset,
// identifier, as sweepd sends every reply.
export function readMessage(data) {
  const bytes = new Uint8Array(data);
  if (bytes.length < 12 || String.fromCharCode(...bytes.subarray(8, 12)) !== 'SWPD') {
    throw new Error('a message that is no sweepd frame');
  }
  return pb.Message.getSizePrefixedRootAsMessage(new flatbuffers.ByteBuffer(bytes));
}

// The reply's body as an object of the class `Type` (e.g. pb.PosedVertices).
export function bodyAs(message, Type) {
  return message.body(new Type());
}
