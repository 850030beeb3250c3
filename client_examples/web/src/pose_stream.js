// PoseStream: asks sweepd for poses at the pace the page draws them. A set is one request per
// visible method for the same pose (a clip frame, or the joint sliders' rotations); a set counts
// as in flight until it is drawn, and kSetsInFlight may be, so that the server deforms the next
// set while the page draws one, and never deforms poses the page would not draw. A set is shown
// when its last reply arrives, all methods at once, so the viewports stay in step.
// pump() sends what is due; drawn() tells it the shown sets are on screen (and returns how many
// there were). poseAt(now) says what to show: {key, request(requestId, fields)} or null, where
// `key` names the pose (nothing is sent again while it stays the same: paused) and `request`
// makes one request's frame for fields {modelId, sequence, method, positions}; `positions` is the
// format asked for ("float16" or "meshopt", vertex_decoding.js decodes either).
import { bodyAs, pb } from './protocol_messages.js';
import { replyPositions } from './vertex_decoding.js';

const kSetsInFlight = 2;

export class PoseStream {
  constructor(connection, modelId, positions, views, stats, onError) {
    Object.assign(this, { connection, modelId, positions, views, stats, onError });
    this.poseAt = () => null;
    this.methods = [];
    this.sequence = 0;
    this.setsInFlight = 0;
    this.setsShown = 0;
    this.sentKey = null;
  }

  setMethods(methods) {
    this.methods = methods;
    this.sentKey = null;  // the newly shown viewports need the pose too
  }

  pump() {
    while (this.setsInFlight < kSetsInFlight && this.methods.length > 0) {
      const pose = this.poseAt(performance.now());
      if (pose === null || pose.key === this.sentKey) return;
      this.send(pose);
    }
  }

  drawn() {
    const shown = this.setsShown;
    this.setsInFlight -= shown;
    this.setsShown = 0;
    this.pump();
    return shown;
  }

  send(pose) {
    this.sentKey = pose.key;
    ++this.setsInFlight;
    const sent = performance.now();
    const methods = this.methods;
    const replies = methods.map((method) => this.connection.request((requestId) => pose.request(
        requestId,
        { modelId: this.modelId, sequence: ++this.sequence, method, positions: this.positions }))
        .then((message) => {
          this.stats.roundTrip(performance.now() - sent, message.bb.capacity());
          return bodyAs(message, pb.PosedVertices);
        }));
    Promise.all(replies).then((posed) => {
      this.views.showSet(methods, posed.map(replyPositions));
      ++this.setsShown;
    }, (error) => {
      --this.setsInFlight;
      this.onError(error);
    });
  }
}
