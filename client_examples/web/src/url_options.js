// The page's settings, from its URL: /viewer?ws=ws://HOST:PORT&token=TOKEN[&model=NAME]
// [&stream=NAME][&methods=sweep,lbs,dqs][&positions=float16|meshopt]. ws: sweepd's WebSocket
// listener (--ws-listen; wss:// with TLS); token: its --token; model: the model's name (default:
// "mannequin" when held, else the first held); stream: instead of clips and sliders, the VMC
// stream of that name (the model a sweepd --vmc-listen poses, docs/vmc.md) on the model it poses (model= is not
// used); methods: the viewports shown at first (default all three); positions: how the
// vertices travel (default float16, 6 bytes a vertex; meshopt, about 4, costs the server about
// 2 ms a 72k pose to encode: protocol/README.md).
function positionFormat(name) {
  if (name !== 'float16' && name !== 'meshopt')
    throw new Error(`positions=${name}: expected float16 or meshopt`);
  return name;
}

export function readUrlOptions(location) {
  const parameters = new URLSearchParams(location.search);
  const ws = parameters.get('ws');
  if (!ws) throw new Error('no sweepd address: open /viewer?ws=ws://HOST:PORT&token=TOKEN');
  return {
    ws,
    token: parameters.get('token') ?? '',
    model: parameters.get('model'),
    stream: parameters.get('stream'),
    methods: (parameters.get('methods') ?? 'sweep,lbs,dqs').split(','),
    positions: positionFormat(parameters.get('positions') ?? 'float16'),
  };
}
