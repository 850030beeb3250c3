// SweepdConnection: one WebSocket session with sweepd (--ws-listen): Hello with the token,
// then requests, each with its own request id. A reply carries the id of the request it answers
// (protocol/README.md), which settles the promise request() returned: resolved with the reply's
// Message; rejected with a SweepdError for an Error reply, and for every request still waiting
// when the session ends (a fatal Error, a close). subscribe() is request() for a reply that goes
// on: after the first, every message with its request id goes to onFrame, a non-fatal Error
// with it to onError, and the session's end to onError too.
import { pb, bodyAs, hello, readMessage } from './protocol_messages.js';

export class SweepdError extends Error {
  constructor(text, fatal) {
    super(text);
    this.fatal = fatal;
  }
}

export class SweepdConnection {
  // Resolves once the server has welcomed us (its Welcome message is `welcome`).
  // `delivery`: pb.PoseDelivery.InOrder or LatestWins (a stream subscription's connection).
  static async open(url, token, delivery = pb.PoseDelivery.InOrder) {
    const socket = new WebSocket(url);
    socket.binaryType = 'arraybuffer';
    await new Promise((resolve, reject) => {
      socket.onopen = resolve;
      socket.onerror = () => reject(new SweepdError(`cannot connect to ${url}`, true));
    });
    const connection = new SweepdConnection(socket);
    connection.welcome = bodyAs(await connection.request((id) => hello(id, token, delivery)), pb.Welcome);
    return connection;
  }

  constructor(socket) {
    this.socket = socket;
    this.nextRequestId = 1;
    this.waiting = new Map();  // request id -> {resolve, reject}
    this.subscriptions = new Map();  // request id -> {onFrame, onError}
    this.closedBecause = null;
    socket.onmessage = (event) => this.receive(event.data);
    socket.onclose = (event) => {
      const reason = event.reason ? `, ${event.reason}` : '';
      this.end(new SweepdError(`the connection closed (code ${event.code}${reason})`, true));
    };
  }

  // `build(requestId)` makes the request's frame; the promise settles with its reply.
  request(build) {
    if (this.closedBecause) return Promise.reject(this.closedBecause);
    const requestId = this.nextRequestId++;
    return new Promise((resolve, reject) => {
      this.waiting.set(requestId, { resolve, reject });
      this.socket.send(build(requestId));
    });
  }

  // Resolves with the first reply (a refusal rejects it and ends the subscription).
  subscribe(build, onFrame, onError) {
    return this.request((requestId) => {
      this.subscriptions.set(requestId, { onFrame, onError });
      return build(requestId);
    });
  }

  receive(data) {
    const message = readMessage(data);
    const requestId = Number(message.requestId());
    const waiter = this.waiting.get(requestId);
    const subscription = this.subscriptions.get(requestId);
    if (message.bodyType() === pb.Body.Error) {
      const error = bodyAs(message, pb.Error);
      const failure = new SweepdError(
          `${pb.ErrorCode[error.code()] ?? 'Internal'}: ${error.message()}`, error.fatal());
      if (error.fatal() || !(waiter || subscription)) return this.end(failure);
      if (!waiter) return subscription.onError(failure);
      this.waiting.delete(requestId);
      this.subscriptions.delete(requestId);
      return waiter.reject(failure);
    }
    if (waiter) {
      this.waiting.delete(requestId);
      waiter.resolve(message);
    } else if (subscription) {
      subscription.onFrame(message);
    }  // else Bye (request id 0): the close follows
  }

  // Ends the session on purpose: its subscriptions hear nothing of it.
  close() {
    this.subscriptions.clear();
    this.end(new SweepdError('closed by the page', true));
  }

  end(reason) {
    this.closedBecause ??= reason;
    for (const waiter of this.waiting.values()) waiter.reject(this.closedBecause);
    for (const subscription of this.subscriptions.values()) subscription.onError(this.closedBecause);
    this.waiting.clear();
    this.subscriptions.clear();
    if (this.socket.readyState === WebSocket.OPEN) this.socket.close();
  }
}
