// SweepdConnection: one WebSocket session with sweepd (--ws-listen): Hello with the token,
// then requests, each with its own request id. A reply carries the id of the request it answers
// (protocol/README.md), which settles the promise request() returned: resolved with the reply's
// Message; rejected with a SweepdError for an Error reply, and for every request still waiting
// when the session ends (a fatal Error, a close).
import { pb, bodyAs, hello, readMessage } from './protocol_messages.js';

export class SweepdError extends Error {
  constructor(text, fatal) {
    super(text);
    this.fatal = fatal;
  }
}

export class SweepdConnection {
  // Resolves once the server has welcomed us (its Welcome message is `welcome`).
  static async open(url, token) {
    const socket = new WebSocket(url);
    socket.binaryType = 'arraybuffer';
    await new Promise((resolve, reject) => {
      socket.onopen = resolve;
      socket.onerror = () => reject(new SweepdError(`cannot connect to ${url}`, true));
    });
    const connection = new SweepdConnection(socket);
    connection.welcome = bodyAs(await connection.request((id) => hello(id, token)), pb.Welcome);
    return connection;
  }

  constructor(socket) {
    this.socket = socket;
    this.nextRequestId = 1;
    this.waiting = new Map();  // request id -> {resolve, reject}
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

  receive(data) {
    const message = readMessage(data);
    const requestId = Number(message.requestId());
    const waiter = this.waiting.get(requestId);
    if (message.bodyType() === pb.Body.Error) {
      const error = bodyAs(message, pb.Error);
      const failure = new SweepdError(
          `${pb.ErrorCode[error.code()] ?? 'Internal'}: ${error.message()}`, error.fatal());
      if (error.fatal() || !waiter) return this.end(failure);
      this.waiting.delete(requestId);
      return waiter.reject(failure);
    }
    if (!waiter) return;  // Bye (request id 0): the close follows
    this.waiting.delete(requestId);
    waiter.resolve(message);
  }

  end(reason) {
    this.closedBecause ??= reason;
    for (const waiter of this.waiting.values()) waiter.reject(this.closedBecause);
    this.waiting.clear();
    if (this.socket.readyState === WebSocket.OPEN) this.socket.close();
  }
}
