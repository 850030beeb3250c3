// StreamWatch: shows a pose stream sweepd receives (VMC, --vmc-listen; docs/vmc.md), the page's
// ?stream=NAME. One subscription (SubscribeStream) per shown method, each on its own connection
// with LatestWins delivery: latest wins drops whatever pose waits on a connection, so methods
// sharing one would drop each other's frames. A frame is drawn as it arrives; the viewports show
// each method's newest frame (neighbouring frames of the stream when one method lags).
// setMethods(methods): subscribes to the newly shown methods, closes the hidden ones'.
// drawn(): how many frames arrived since the last call. figures(): per method, what came: the
// frames, the last one's stream sequence, the frames the server dropped for this page (it was
// slower than the stream), the vertex count and the mean vertex of the last frame (what the
// headless test compares with its own subscriber's).
import { SweepdConnection } from './sweepd_connection.js';
import { bodyAs, pb, subscribeStream } from './protocol_messages.js';
import { replyPositions } from './vertex_decoding.js';
import * as THREE from 'three';

function meanVertex(positions) {
  const read = positions instanceof Float32Array ? (v) => v : THREE.DataUtils.fromHalfFloat;
  const sum = [0, 0, 0];
  for (let i = 0; i < positions.length; ++i) sum[i % 3] += read(positions[i]);
  return sum.map((total) => total / (positions.length / 3));
}

export class StreamWatch {
  // `modelId`: the model whose rest mesh the views hold; a stream posing another is an error.
  constructor({ url, token, stream, modelId, positions, views, stats, onFrame, onError }) {
    Object.assign(this, { url, token, stream, modelId, positions, views, stats, onFrame, onError });
    this.watched = new Map();  // method -> {connection, frames, sequence, dropped, last}
    this.arrived = 0;
  }

  setMethods(methods) {
    for (const [method, { connection }] of this.watched) {
      if (methods.includes(method)) continue;
      connection?.close();
      this.watched.delete(method);
    }
    for (const method of methods) {
      if (!this.watched.has(method)) this.watch(method).catch((error) => this.onError(error));
    }
  }

  async watch(method) {
    const watched = { connection: null, frames: 0, sequence: 0, dropped: 0, last: null };
    this.watched.set(method, watched);
    const connection =
        await SweepdConnection.open(this.url, this.token, pb.PoseDelivery.LatestWins);
    if (this.watched.get(method) !== watched) return connection.close();  // hidden meanwhile
    watched.connection = connection;
    const reply = bodyAs(await connection.subscribe(
        (id) => subscribeStream(id, this.stream, { method, positions: this.positions }),
        (message) => this.show(method, watched, bodyAs(message, pb.PosedVertices),
                               message.bb.capacity()),
        (error) => this.onError(error)), pb.StreamSubscribed);
    if (reply.modelId() !== this.modelId) {
      throw new Error(`the stream '${this.stream}' poses model ${reply.modelId()}, ` +
                      `not the model ${this.modelId} the page loaded`);
    }
  }

  show(method, watched, posed, bytes) {
    if (this.watched.get(method) !== watched) return;
    watched.last = replyPositions(posed);
    watched.frames += 1;
    watched.sequence = Number(posed.sequence());
    watched.dropped += posed.droppedBefore();
    this.views.showSet([method], [watched.last]);
    this.stats.frameReceived(bytes);
    this.arrived += 1;
    this.onFrame(watched.sequence);
  }

  drawn() {
    const arrived = this.arrived;
    this.arrived = 0;
    return arrived;
  }

  figures() {
    const figures = {};
    for (const [method, { frames, sequence, dropped, last }] of this.watched) {
      figures[method] = { frames, sequence, dropped, vertexCount: last ? last.length / 3 : 0,
                          meanVertex: last ? meanVertex(last) : null };
    }
    return figures;
  }
}
