// Reads an MCAP file with @mcap/core (Foxglove's reader, not ours) twice: indexed (through
// the summary, chunk indexes and message indexes) and streamed (record by record, checking
// CRCs), and decodes every message with Foxglove's ros2msg parser and CDR deserializer
// from the schema the file carries. Prints one JSON object: profile, channels with topic,
// schema name and encoding, message encoding, count, a SHA-256 of each message's payload
// and each decoded message's frame (header.frame_id, or client, or the first transform's
// child_frame_id) in order; every decoded message is encoded again and must give its own
// bytes. Exits 1 when the two readings disagree or a reader refuses the
// file or a message.
import { McapIndexedReader, McapStreamReader } from "@mcap/core";
import { parse as parseMessageDefinition } from "@foxglove/rosmsg";
import { MessageReader, MessageWriter } from "@foxglove/rosmsg2-serialization";
import { decompress as zstdDecompress } from "fzstd";
import lz4 from "lz4js";
import { createHash } from "node:crypto";
import { open, readFile } from "node:fs/promises";

const decompressHandlers = {
  zstd: (data, size) => zstdDecompress(data, new Uint8Array(Number(size))),
  lz4: (data) => Uint8Array.from(lz4.decompress(data)),
};

function sha256(bytes) {
  return createHash("sha256").update(bytes).digest("hex");
}

async function readIndexed(path) {
  const handle = await open(path, "r");
  const readable = {
    size: async () => BigInt((await handle.stat()).size),
    read: async (offset, length) => {
      const buffer = new Uint8Array(Number(length));
      await handle.read(buffer, 0, Number(length), Number(offset));
      return buffer;
    },
  };
  const reader = await McapIndexedReader.Initialize({ readable, decompressHandlers });
  const channels = {};
  for (const [id, channel] of reader.channelsById) {
    const schema = reader.schemasById.get(channel.schemaId);
    channels[id] = {
      topic: channel.topic,
      message_encoding: channel.messageEncoding,
      schema_name: schema?.name ?? "",
      schema_encoding: schema?.encoding ?? "",
      schema_data: schema ? Buffer.from(schema.data).toString("utf8") : "",
      metadata: Object.fromEntries(channel.metadata),
      count: 0,
      payload_sha256: [],
      frames: [],
      definitions: schema ? parseMessageDefinition(Buffer.from(schema.data).toString("utf8"), { ros2: true }) : null,
    };
    channels[id].decoder = new MessageReader(channels[id].definitions);
    channels[id].encoder = new MessageWriter(channels[id].definitions);
  }
  for await (const message of reader.readMessages()) {
    const channel = channels[message.channelId];
    channel.count += 1;
    channel.payload_sha256.push(sha256(message.data));
    const decoded = channel.decoder.readMessage(message.data);
    channel.frames.push(decoded.header?.frame_id ?? decoded.client ?? decoded.transforms?.[0]?.child_frame_id ??
      (decoded.clock ? `clock_${decoded.clock.sec}` : null));
    // Encoded again through the same schema, the message must give its own bytes (up to
    // the trailing alignment padding): the schema describes every field, not just the first.
    const again = channel.encoder.writeMessage(decoded);
    const original = Buffer.from(message.data);
    const same = again.length <= original.length && original.subarray(0, again.length).equals(Buffer.from(again)) &&
      original.subarray(again.length).every((byte) => byte === 0);
    if (!same) throw new Error(`${channel.topic}: message ${channel.count} does not re-encode to its bytes through the file's schema`);
  }
  for (const channel of Object.values(channels)) {
    delete channel.decoder;
    delete channel.encoder;
    delete channel.definitions;
  }
  const statistics = reader.statistics;
  await handle.close();
  return {
    profile: reader.header.profile,
    library: reader.header.library,
    message_count: Number(statistics?.messageCount ?? 0),
    channels: Object.values(channels),
  };
}

async function readStreamed(path) {
  const stream = new McapStreamReader({ decompressHandlers, validateCrcs: true });
  stream.append(await readFile(path));
  const hashes = {};
  const topics = {};
  for (let record; (record = stream.nextRecord()); ) {
    if (record.type === "Channel") topics[record.id] = record.topic;
    if (record.type === "Message") (hashes[topics[record.channelId]] ??= []).push(sha256(record.data));
  }
  if (!stream.done()) throw new Error("the stream reader did not reach the end of the file");
  return hashes;
}

const path = process.argv[2];
try {
  const indexed = await readIndexed(path);
  const streamed = await readStreamed(path);
  for (const channel of indexed.channels) {
    const other = streamed[channel.topic] ?? [];
    if (JSON.stringify(other) !== JSON.stringify(channel.payload_sha256))
      throw new Error(`${channel.topic}: the indexed and the streamed readings differ`);
  }
  console.log(JSON.stringify(indexed));
} catch (error) {
  console.error(`read_mcap.mjs: ${path}: ${error.message}`);
  process.exit(1);
}
