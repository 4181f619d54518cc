// Serializes and deserializes ROS 2 messages with foxglove's CDR implementation, for semfuse's
// interop test. Standard ROS 2 types come from @foxglove/rosmsg-msgs-common (Humble); semfuse's
// types are parsed by @foxglove/rosmsg from the .msg files of idl/ros2/semfuse_msgs.
//
//   node rosmsg_cdr.mjs encode TYPE IN.flat OUT.cdr --msg-dir DIR
//   node rosmsg_cdr.mjs decode TYPE IN.cdr OUT.flat --msg-dir DIR
//
// TYPE is "pkg/Name" (sensor_msgs/Image, semfuse/Frame). A .flat file holds one leaf per line,
// `path=value`, with paths like `header.stamp.sec` or `transforms[0].child_frame_id` and values
// as JSON literals; a .cdr file is the 4-byte encapsulation header plus the CDR body.
import { readFileSync, readdirSync, writeFileSync } from "node:fs";
import { basename, join } from "node:path";
import { createRequire } from "node:module";

const require = createRequire(import.meta.url);
const { parse } = require("@foxglove/rosmsg");
const { ros2humble } = require("@foxglove/rosmsg-msgs-common");
const { MessageReader, MessageWriter } = require("@foxglove/rosmsg2-serialization");

function usage(code) {
  (code ? console.error : console.log)(
    "usage: node rosmsg_cdr.mjs encode|decode TYPE IN OUT --msg-dir DIR\n" +
      "  encode: IN is a .flat file (path=JSON value per line), OUT the CDR bytes\n" +
      "  decode: IN is CDR bytes, OUT the .flat file");
  process.exit(code);
}

// "pkg/msg/Name" and "pkg/Name" are one type; a bare "Name" is in `pkg`.
function qualify(type, pkg) {
  const parts = type.split("/");
  if (parts.length === 3) return `${parts[0]}/${parts[2]}`;
  if (parts.length === 1) return `${pkg}/${type}`;
  return type;
}

function semfuseDefinitions(msgDir) {
  const defs = [];
  for (const file of readdirSync(msgDir).filter((f) => f.endsWith(".msg"))) {
    const [root] = parse(readFileSync(join(msgDir, file), "utf8"), { ros2: true, skipTypeFixup: true });
    root.name = `semfuse/${basename(file, ".msg")}`;
    for (const field of root.definitions) {
      if (field.isComplex) field.type = qualify(field.type, "semfuse");
    }
    defs.push(root);
  }
  return defs;
}

function definitionsFor(type, msgDir) {
  const all = new Map(Object.entries(ros2humble));
  for (const def of semfuseDefinitions(msgDir)) all.set(def.name, def);
  const root = all.get(type);
  if (!root) throw new Error(`unknown type ${type}`);
  return [root, ...[...all.values()].filter((d) => d !== root)];
}

function setPath(object, path, value) {
  const keys = path.match(/[^.[\]]+/g);
  let node = object;
  keys.forEach((key, i) => {
    const last = i === keys.length - 1;
    const nextIsIndex = !last && /^\d+$/.test(keys[i + 1]);
    if (last) node[key] = value;
    else node = node[key] ??= nextIsIndex ? [] : {};
  });
}

// JSON, except that integers beyond 2^53 stay exact (uint64/int64 fields).
function parseValue(text) {
  if (/^-?\d+$/.test(text) && !Number.isSafeInteger(Number(text))) return BigInt(text);
  return JSON.parse(text);
}

function readFlat(text) {
  const message = {};
  for (const line of text.split("\n")) {
    if (!line.trim()) continue;
    const eq = line.indexOf("=");
    if (eq < 0) throw new Error(`bad line: ${line}`);
    setPath(message, line.slice(0, eq), parseValue(line.slice(eq + 1)));
  }
  return message;
}

function flatten(value, path, out) {
  if (typeof value === "bigint") out.push(`${path}=${value.toString()}`);
  else if (ArrayBuffer.isView(value) || Array.isArray(value)) {
    out.push(`${path}.length=${value.length}`);
    Array.from(value).forEach((v, i) => flatten(v, `${path}[${i}]`, out));
  } else if (value !== null && typeof value === "object") {
    for (const [k, v] of Object.entries(value)) flatten(v, path ? `${path}.${k}` : k, out);
  } else out.push(`${path}=${JSON.stringify(value)}`);
  return out;
}

const args = process.argv.slice(2);
if (args.includes("--help") || args.includes("-h")) usage(0);
const dirAt = args.indexOf("--msg-dir");
if (args.length !== 6 || dirAt !== 4) usage(2);
const [mode, type, input, output] = args;
try {
  const definitions = definitionsFor(type, args[5]);
  if (mode === "encode") {
    writeFileSync(output, new MessageWriter(definitions).writeMessage(readFlat(readFileSync(input, "utf8"))));
  } else if (mode === "decode") {
    const reader = new MessageReader(definitions);
    const bytes = readFileSync(input);
    const message = reader.readMessage(bytes);
    // XCDR allows padding the sample to 4 bytes; the options' low two bits say how much.
    const unread = bytes.length - reader.lastReadByteLength();
    if (unread > (bytes[3] & 3)) throw new Error(`${input}: ${unread} bytes left after a ${type}`);
    writeFileSync(output, flatten(message, "", []).join("\n") + "\n");
  } else {
    usage(2);
  }
} catch (e) {
  console.error(`rosmsg_cdr: ${e.message}`);
  process.exit(1);
}
