// The positions of a PosedVertices reply as the page draws them (protocol/README.md, "Compact
// vertex streams"): float16 halves as they came (a view into the reply: the GPU takes them as
// they are), or a meshopt stream decoded to float32 metres — int32 grid steps from the reply's
// own origin, through npm meshoptimizer's decoder (WebAssembly, bundled: no fetch).
// decoderReady: resolves once the decoder can run; await it before the first meshopt reply.
// replyPositions(reply): Uint16Array (float16) or Float32Array, 3 values per vertex.
import { MeshoptDecoder } from 'meshoptimizer';

export const decoderReady = MeshoptDecoder.ready;

export function replyPositions(reply) {
  const stream = reply.positionsMeshoptArray();
  if (stream === null) return reply.positionsF16Array();
  const count = reply.vertexCount();
  const steps = new Int32Array(3 * count);
  MeshoptDecoder.decodeVertexBuffer(new Uint8Array(steps.buffer), count, 12, stream);
  const origin = reply.positionOrigin();
  const step = reply.positionStep();
  const [ox, oy, oz] = [origin.x(), origin.y(), origin.z()];
  const positions = new Float32Array(3 * count);
  for (let i = 0; i < positions.length; i += 3) {
    positions[i] = ox + step * steps[i];
    positions[i + 1] = oy + step * steps[i + 1];
    positions[i + 2] = oz + step * steps[i + 2];
  }
  return positions;
}
