// Runs the Khronos glTF validator over .glb files: prints each file's error, warning and
// info counts and its errors and warnings; exits 1 when any file has an error or a warning.
const validator = require('gltf-validator');
const fs = require('fs');

async function main(files) {
    let bad = 0;
    for (const file of files) {
        const report = await validator.validateBytes(new Uint8Array(fs.readFileSync(file)));
        const issues = report.issues;
        console.log(`${file}: ${issues.numErrors} errors, ${issues.numWarnings} warnings, ${issues.numInfos} infos`);
        for (const m of issues.messages)
            if (m.severity <= 1) console.log(`  ${m.severity === 0 ? 'error' : 'warning'} ${m.code}: ${m.message} ${m.pointer || ''}`);
        if (issues.numErrors + issues.numWarnings > 0) bad++;
    }
    process.exit(bad > 0 ? 1 : 0);
}
main(process.argv.slice(2)).catch(e => { console.error(e); process.exit(2); });
