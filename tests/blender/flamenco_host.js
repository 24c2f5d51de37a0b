// Runs a Flamenco job compiler script the way Flamenco Manager calls it, with
// the globals such a script uses (author.Task, author.Command, print) and a job
// whose addTask records the tasks; prints the job type's label, its setting
// keys and the tasks as JSON.
//
// usage: node flamenco_host.js JOB_TYPE.js 'SETTINGS_JSON'
"use strict";
const fs = require("fs");
const vm = require("vm");

const [scriptPath, settingsJson] = process.argv.slice(2);
const author = {
    Task(name, type) {
        return { name, type, commands: [], addCommand(command) { this.commands.push(command); } };
    },
    Command(name, parameters) {
        return { name, parameters };
    },
};
const context = vm.createContext({ author, print: console.log });
const source = fs.readFileSync(scriptPath, "utf8");
vm.runInContext(`${source}\n;globalThis.JOB_TYPE = JOB_TYPE; globalThis.compileJob = compileJob;`, context,
                { filename: scriptPath });
const tasks = [];
const job = {
    settings: JSON.parse(settingsJson),
    addTask(task) { tasks.push({ name: task.name, type: task.type, commands: task.commands }); },
};
context.compileJob(job);
console.log(JSON.stringify({
    label: context.JOB_TYPE.label,
    settings: context.JOB_TYPE.settings.map((s) => s.key),
    tasks,
}));
