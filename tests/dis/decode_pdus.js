#!/usr/bin/env node
// Decodes the DIS PDUs lpss-dis sends with open-dis (an implementation no one here wrote), one JSON line
// per datagram on stdout, so that a test can compare what a third-party receiver sees with the world.
//
//   node tests/dis/decode_pdus.js PORT [--seconds S] [--count N] [--bind ADDRESS]
//
// Listens on UDP ADDRESS:PORT (127.0.0.1 by default; 0.0.0.0 to hear broadcasts; PORT 0 picks a free
// port). Exits after S seconds (10 by default, so that a test can never hang on it) or after N
// datagrams, whichever comes first. Once bound it says "listening on ADDRESS:PORT" on stderr: a test
// starts sending after that line. At the end it prints a count on stderr.
//
// A decoded Entity State PDU gives
//   {pduType, protocolVersion, exerciseID, length, timestamp, site, application, entity, forceId,
//    entityType: [kind, domain, country, category, subcategory, specific, extra], location: [x, y, z],
//    velocity: [...], orientation: [psi, theta, phi], appearance, drAlgorithm, drLinearAcceleration: [...],
//    drAngularVelocity: [...], markingCharacterSet, marking, capabilities, receivedMs}
// (float fields are the float32 values exactly; the location keeps its full double precision). Another
// PDU type gives its header fields only; a datagram open-dis cannot decode gives {error, bytes,
// receivedMs}. Both count towards --count.
'use strict';

const dgram = require('dgram');
const path = require('path');

// The DIS 7 build of open-dis: its package's main is the DIS 6 one. Found through NODE_PATH, or beside
// this script in tests/node.
function loadOpenDis7() {
    const build = 'open-dis/dist/dis7.min.js';
    try {
        return require(build);
    } catch (notOnNodePath) {
        return require(path.join(__dirname, '..', 'node', 'node_modules', build));
    }
}

function parseArguments(argv) {
    const options = {port: null, seconds: 10, count: Infinity, bind: '127.0.0.1'};
    for (let i = 0; i < argv.length; ++i) {
        const argument = argv[i];
        const value = () => {
            if (i + 1 >= argv.length) throw new Error(`${argument} needs a value`);
            return argv[++i];
        };
        if (argument === '--seconds') options.seconds = Number(value());
        else if (argument === '--count') options.count = Number(value());
        else if (argument === '--bind') options.bind = value();
        else if (options.port === null && /^\d+$/.test(argument)) options.port = Number(argument);
        else throw new Error(`unexpected argument ${argument}`);
    }
    if (options.port === null || options.port > 65535) throw new Error('a UDP port (0-65535) is needed');
    if (!(options.seconds > 0)) throw new Error('--seconds must be a positive number');
    if (!(options.count >= 1)) throw new Error('--count must be at least 1');
    return options;
}

const vector = (v) => [v.x, v.y, v.z];

function describe(pdu, receivedMs) {
    const header = {
        pduType: pdu.pduType,
        protocolVersion: pdu.protocolVersion,
        exerciseID: pdu.exerciseID,
        length: pdu.length,
        timestamp: pdu.timestamp,
    };
    if (pdu.pduType !== 1) return {...header, receivedMs};
    const type = pdu.entityType;
    const deadReckoning = pdu.deadReckoningParameters;
    return {
        ...header,
        site: pdu.entityID.siteID,
        application: pdu.entityID.applicationID,
        entity: pdu.entityID.entityID,
        forceId: pdu.forceId,
        entityType: [type.entityKind, type.domain, type.country, type.category, type.subcategory,
                     type.specific, type.extra],
        location: vector(pdu.entityLocation),
        velocity: vector(pdu.entityLinearVelocity),
        orientation: [pdu.entityOrientation.psi, pdu.entityOrientation.theta, pdu.entityOrientation.phi],
        appearance: pdu.entityAppearance,
        drAlgorithm: deadReckoning.deadReckoningAlgorithm,
        drLinearAcceleration: vector(deadReckoning.entityLinearAcceleration),
        drAngularVelocity: vector(deadReckoning.entityAngularVelocity),
        markingCharacterSet: pdu.marking.characterSet,
        marking: pdu.marking.getMarking(),
        capabilities: pdu.capabilities,
        receivedMs,
    };
}

function main() {
    let options;
    try {
        options = parseArguments(process.argv.slice(2));
    } catch (error) {
        process.stderr.write(`decode_pdus.js: ${error.message}\n` +
                             'usage: node decode_pdus.js PORT [--seconds S] [--count N] [--bind ADDRESS]\n');
        process.exitCode = 2;
        return;
    }
    const dis = loadOpenDis7();
    const factory = new dis.PduFactory();
    const socket = dgram.createSocket({type: 'udp4', reuseAddr: true});
    let received = 0;
    let timer = null;
    let open = true;

    // Closing the socket and the timer lets the event loop end once stdout is written out.
    const finish = (why) => {
        if (!open) return;
        open = false;
        if (timer !== null) clearTimeout(timer);
        socket.close();
        process.stderr.write(`decode_pdus.js: ${received} datagrams, stopped on ${why}\n`);
    };

    socket.on('message', (message) => {
        if (!open) return;
        const receivedMs = Date.now();
        // open-dis reads through a DataView, which wants the datagram's own ArrayBuffer (a Buffer may
        // be a view into a larger pool).
        const bytes = message.buffer.slice(message.byteOffset, message.byteOffset + message.length);
        let line;
        try {
            line = describe(factory.createPdu(bytes), receivedMs);
        } catch (error) {
            line = {error: String(error && error.message ? error.message : error), bytes: message.length,
                    receivedMs};
        }
        process.stdout.write(JSON.stringify(line) + '\n');
        ++received;
        if (received >= options.count) finish('count');
    });
    socket.on('error', (error) => {
        process.exitCode = 1;
        finish(`error: ${error.message}`);
    });
    socket.bind(options.port, options.bind, () => {
        const address = socket.address();
        process.stderr.write(`listening on ${address.address}:${address.port}\n`);
        timer = setTimeout(() => finish('time'), options.seconds * 1000);
    });
}

main();
