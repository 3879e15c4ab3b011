// A Foxglove WebSocket client made of Foxglove's own packages (@foxglove/ws-protocol's
// FoxgloveClient, @foxglove/rosmsg and @foxglove/rosmsg2-serialization to decode CDR with
// the advertised schema): what the Foxglove app does, without a browser.
//
//   node foxglove_client.mjs URL --topics /a,/b [--until /a:N,/b:M] [--timeout S]
//        [--stall S] [--leave-after-bytes N]
//
// Subscribes to the topics as soon as they are advertised, decodes every message and prints
// one JSON object at the end: the server's info, every advertise and unadvertise, statuses,
// the server's time messages (ns),
// and per topic the decoded messages in short (the bridge's receive time, when it arrived
// here, header stamps, cloud sizes, room walls).
// SIGTERM ends it the same way. --until stops once each topic has that many messages; --stall stops
// reading from the socket for S seconds after subscribing (a client that falls behind);
// --leave-after-bytes drops the TCP connection in the middle of the first message larger
// than N bytes.
import wsp from "@foxglove/ws-protocol";
import { parse } from "@foxglove/rosmsg";
import { MessageReader } from "@foxglove/rosmsg2-serialization";
import WebSocket from "ws";

const { FoxgloveClient } = wsp;

function options(argv) {
  const out = { url: argv[0], topics: [], until: {}, timeout: 120, stall: 0, leaveAfterBytes: 0 };
  for (let i = 1; i < argv.length; i += 2) {
    const [key, value] = [argv[i], argv[i + 1]];
    if (key === "--topics") out.topics = value.split(",");
    else if (key === "--until")
      for (const entry of value.split(",")) {
        const [topic, count] = entry.split(":");
        out.until[topic] = Number(count);
      }
    else if (key === "--timeout") out.timeout = Number(value);
    else if (key === "--stall") out.stall = Number(value);
    else if (key === "--leave-after-bytes") out.leaveAfterBytes = Number(value);
    else throw new Error(`unknown option ${key}`);
  }
  return out;
}

const stamp = (header) => header.stamp.sec + header.stamp.nanosec * 1e-9;

// What a message says in short, by type: enough to compare with `scanbus echo`.
function summary(schemaName, message) {
  if (schemaName === "sensor_msgs/msg/PointCloud2")
    return { stamp: stamp(message.header), frame_id: message.header.frame_id, width: message.width,
             height: message.height, point_step: message.point_step, data_bytes: message.data.length,
             fields: message.fields.map((f) => f.name) };
  if (schemaName === "scanbus/msg/RoomMeasurement")
    return { stamp: stamp(message.header), floor_area: message.floor_area, status: message.status,
             walls: message.walls.map((w) => ({ length: w.length })) , message: message.message};
  if (message.header) return { stamp: stamp(message.header) };
  return {};
}

const opts = options(process.argv.slice(2));
const result = { serverInfo: null, advertised: [], unadvertised: [], statuses: [], messages: {}, times: [],
                 errors: [] };
const channels = new Map(); // id -> { topic, schemaName, reader }
const subscriptions = new Map(); // subscription id -> channel id

const ws = new WebSocket(opts.url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
const client = new FoxgloveClient({ ws });
let finished = false;

function finish(code) {
  if (finished) return;
  finished = true;
  console.log(JSON.stringify(result));
  try { client.close(); } catch (e) { /* already closed */ }
  setTimeout(() => process.exit(code), 100);
}

function done() {
  return Object.entries(opts.until).every(([topic, count]) => (result.messages[topic] ?? []).length >= count);
}

client.on("serverInfo", (info) => { result.serverInfo = info; });
client.on("status", (status) => { result.statuses.push(status); });
client.on("time", ({ timestamp }) => { result.times.push(timestamp.toString()); });
client.on("error", (error) => { result.errors.push(String(error)); });
client.on("close", () => { if (!finished) { result.errors.push("closed by the server"); finish(1); } });
client.on("advertise", (list) => {
  for (const channel of list) {
    result.advertised.push({ id: channel.id, topic: channel.topic, encoding: channel.encoding,
                             schemaName: channel.schemaName, schemaEncoding: channel.schemaEncoding });
    const reader = new MessageReader(parse(channel.schema, { ros2: true }));
    channels.set(channel.id, { topic: channel.topic, schemaName: channel.schemaName, reader });
    if (opts.topics.includes(channel.topic)) {
      subscriptions.set(client.subscribe(channel.id), channel.id);
      if (opts.stall > 0 && ws._socket) {
        ws._socket.pause(); // read nothing: the server's sends to us back up
        setTimeout(() => ws._socket.resume(), opts.stall * 1000);
      }
    }
  }
});
client.on("unadvertise", (ids) => { for (const id of ids) result.unadvertised.push(channels.get(id)?.topic ?? id); });
client.on("message", ({ subscriptionId, timestamp, data }) => {
  const arrived = BigInt(Math.round((performance.timeOrigin + performance.now()) * 1e3)) * 1000n;  // ns, µs steps
  const channel = channels.get(subscriptions.get(subscriptionId));
  if (!channel) { result.errors.push(`message for unknown subscription ${subscriptionId}`); return; }
  const bytes = new Uint8Array(data.buffer, data.byteOffset, data.byteLength);
  const entry = { receive_ns: timestamp.toString(), arrive_ns: arrived.toString(), bytes: bytes.length };
  try {
    Object.assign(entry, summary(channel.schemaName, channel.reader.readMessage(bytes)));
  } catch (error) {
    entry.decode_error = String(error);
  }
  (result.messages[channel.topic] ??= []).push(entry);
  if (Object.keys(opts.until).length > 0 && done()) finish(0);
});
if (opts.leaveAfterBytes > 0)
  ws.on("open", () => {
    let seen = 0;
    ws._socket.on("data", (chunk) => {
      seen += chunk.length;
      if (seen > opts.leaveAfterBytes) { ws._socket.destroy(); finish(0); }
    });
  });
setTimeout(() => finish(Object.keys(opts.until).length > 0 ? 1 : 0), opts.timeout * 1000);
process.on("SIGTERM", () => finish(0));
