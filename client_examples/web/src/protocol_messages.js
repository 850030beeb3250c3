// The viewer's requests as sweepd frames, and replies read back: FlatBuffers code that flatc
// generates from protocol/sweepd.fbs at build time (imported as @sweepd/protocol), framed as
// protocol/README.md says: size-prefixed, identifier "SWPD", one frame per WebSocket message.
import * as flatbuffers from 'flatbuffers';
import * as pb from '@sweepd/protocol';

export { pb };

const kVersionMajor = 1;
const kVersionMinor = 15;  // SubscribeStream (the page's ?stream=)

export const kMethods = {
  sweep: pb.DeformMethod.Sweep,
  lbs: pb.DeformMethod.Lbs,
  dqs: pb.DeformMethod.Dqs,
};

const kPositionFormats = {
  float16: pb.PositionFormat.Float16,
  meshopt: pb.PositionFormat.Meshopt,
};

// Tables are built field by field (start, add, end), never with flatc's createX helpers: those
// take every field positionally, so a field the schema gains (an additive minor version) would
// be written from an `undefined` argument and break the frame.

// One frame: `body(builder)` writes the body and returns [type, offset].
function frame(requestId, body) {
  const builder = new flatbuffers.Builder(1024);
  const [type, offset] = body(builder);
  pb.Message.startMessage(builder);
  pb.Message.addRequestId(builder, BigInt(requestId));
  pb.Message.addBodyType(builder, type);
  pb.Message.addBody(builder, offset);
  const message = pb.Message.endMessage(builder);
  builder.finishSizePrefixed(message, 'SWPD');
  return builder.asUint8Array();
}

// `delivery`: pb.PoseDelivery.InOrder (the page's own poses) or LatestWins (a stream).
export function hello(requestId, token, delivery = pb.PoseDelivery.InOrder) {
  return frame(requestId, (b) => {
    const tokenOffset = b.createString(token), nameOffset = b.createString('sweepd viewer');
    pb.Hello.startHello(b);
    pb.Hello.addVersionMajor(b, kVersionMajor);
    pb.Hello.addVersionMinor(b, kVersionMinor);
    pb.Hello.addAuthToken(b, tokenOffset);
    pb.Hello.addClientName(b, nameOffset);
    pb.Hello.addDelivery(b, delivery);
    return [pb.Body.Hello, pb.Hello.endHello(b)];
  });
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
  return frame(requestId, (b) => {
    pb.MeshRequest.startMeshRequest(b);
    pb.MeshRequest.addModelId(b, modelId);
    return [pb.Body.MeshRequest, pb.MeshRequest.endMeshRequest(b)];
  });
}

export function uploadClip(requestId, name, bvh, lengthScale) {
  return frame(requestId, (b) => {
    const nameOffset = b.createString(name), bvhOffset = b.createString(bvh);
    pb.UploadClip.startUploadClip(b);
    pb.UploadClip.addName(b, nameOffset);
    pb.UploadClip.addBvh(b, bvhOffset);
    pb.UploadClip.addLengthScale(b, lengthScale);
    return [pb.Body.UploadClip, pb.UploadClip.endUploadClip(b)];
  });
}

// The pose fields the pose requests and SubscribeStream share: positions in the format asked for (float16 or
// meshopt), no normals (the page shades flat), no features.
function poseFields(b, pose) {
  pb.Pose.startPose(b);
  pb.Pose.addModelId(b, pose.modelId);
  pb.Pose.addSequence(b, BigInt(pose.sequence));
  pb.Pose.addMethod(b, kMethods[pose.method]);
  pb.Pose.addPositions(b, kPositionFormats[pose.positions]);
  return pb.Pose.endPose(b);
}

// Frame `frame` of a held clip, wrapping past its end.
export function poseFromClip(requestId, pose, clipId, frameIndex) {
  return frame(requestId, (b) => {
    const clipIdOffset = b.createString(clipId);
    const poseOffset = poseFields(b, pose);
    // flatc 2.0.8's TypeScript writes an optional scalar only when it differs from 0: frame 0
    // would be absent (the server then finds neither frame nor time). Force it out.
    pb.ClipFrame.startClipFrame(b);
    pb.ClipFrame.addClipId(b, clipIdOffset);
    b.forceDefaults(true);
    pb.ClipFrame.addFrame(b, frameIndex);
    b.forceDefaults(false);
    pb.ClipFrame.addLoop(b, true);
    const clip = pb.ClipFrame.endClipFrame(b);
    pb.PoseFromClip.startPoseFromClip(b);
    pb.PoseFromClip.addPose(b, poseOffset);
    pb.PoseFromClip.addClip(b, clip);
    return [pb.Body.PoseFromClip, pb.PoseFromClip.endPoseFromClip(b)];
  });
}

// The frames of the stream `stream` (VMC, docs/vmc.md), each deformed and sent as `pose` says
// (its method and positions; the stream gives the rotations): answered by StreamSubscribed,
// then a PosedVertices per frame, all with this request's id.
export function subscribeStream(requestId, stream, pose) {
  return frame(requestId, (b) => {
    const streamOffset = b.createString(stream);
    const poseOffset = poseFields(b, { ...pose, modelId: 0, sequence: 0 });
    pb.SubscribeStream.startSubscribeStream(b);
    pb.SubscribeStream.addStream(b, streamOffset);
    pb.SubscribeStream.addPose(b, poseOffset);
    return [pb.Body.SubscribeStream, pb.SubscribeStream.endSubscribeStream(b)];
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
    pb.PoseByName.startPoseByName(b);
    pb.PoseByName.addPose(b, poseOffset);
    pb.PoseByName.addJointNames(b, nameOffsets);
    pb.PoseByName.addRotations(b, rotationOffsets);
    return [pb.Body.PoseByName, pb.PoseByName.endPoseByName(b)];
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
