// The page's settings, from its URL: /viewer?ws=ws://HOST:PORT&token=TOKEN[&model=NAME]
// [&methods=sweep,lbs,dqs]. ws: sweepd's WebSocket listener (--ws-listen; wss:// with TLS);
// token: its --token; model: the model's name (default: "mannequin" when held, else the first
// held); methods: the viewports shown at first (default all three).
export function readUrlOptions(location) {
  const parameters = new URLSearchParams(location.search);
  const ws = parameters.get('ws');
  if (!ws) throw new Error('no sweepd address: open /viewer?ws=ws://HOST:PORT&token=TOKEN');
  return {
    ws,
    token: parameters.get('token') ?? '',
    model: parameters.get('model'),
    methods: (parameters.get('methods') ?? 'sweep,lbs,dqs').split(','),
  };
}
