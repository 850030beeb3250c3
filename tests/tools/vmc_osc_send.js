// A VMC sender on the npm `osc` package (osc.js, the OSC library of Node and browser VMC
// tools), for tests/server/daemon_vmc_test.cpp: each line on stdin is one frame as JSON,
// {"seconds": T, "bones": [[NAME, px, py, pz, qx, qy, qz, qw], ...]} (Unity's frame), sent as
// one bundle: a /VMC/Ext/Bone/Pos per bone, then /VMC/Ext/OK 1 and /VMC/Ext/T T, as VSeeFace
// sends a frame. Every number goes out as an OSC float32 ('f'): the test writes float32 values,
// which a JS number holds exactly, so the floats on the wire are the test's own.
//
//   NODE_PATH=.tools/node_modules node tests/tools/vmc_osc_send.js --port PORT < frames.jsonl
//
// Exits 0 once stdin ends and every frame was sent; 1 with the reason otherwise.
const osc = require('osc');
const readline = require('node:readline');
const { parseArgs } = require('node:util');

const { values: options } = parseArgs({ options: { port: { type: 'string' } } });
if (!options.port) throw new Error('--port is required');

const float = (value) => ({ type: 'f', value });

function frameBundle({ seconds, bones }) {
  const packets = bones.map(([name, ...transform]) => ({
    address: '/VMC/Ext/Bone/Pos',
    args: [{ type: 's', value: name }, ...transform.map(float)],
  }));
  packets.push({ address: '/VMC/Ext/OK', args: [{ type: 'i', value: 1 }] });
  packets.push({ address: '/VMC/Ext/T', args: [float(seconds)] });
  return { timeTag: { raw: [0, 1] }, packets };  // OSC's "immediately"
}

const port = new osc.UDPPort({
  localAddress: '127.0.0.1', localPort: 0,
  remoteAddress: '127.0.0.1', remotePort: Number(options.port), metadata: true,
});
port.on('error', (error) => {
  console.error(`vmc_osc_send: ${error.message}`);
  process.exit(1);
});
port.on('ready', () => {
  const lines = readline.createInterface({ input: process.stdin });
  lines.on('line', (line) => {
    if (line.trim() !== '') port.send(frameBundle(JSON.parse(line)));
  });
  lines.on('close', () => port.close());
});
port.open();
