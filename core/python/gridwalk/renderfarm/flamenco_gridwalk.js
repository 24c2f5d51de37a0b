// Gridwalk Render: a Flamenco 3 job type that renders a .blend's frames with
// the GRIDWALK engine through `blender -b`.
//
// Install: copy this file into the `scripts` folder next to the
// flamenco-manager executable (create the folder if needed) and restart the
// Manager; "Gridwalk Render" then appears among the job types in Flamenco's
// Blender add-on. Every worker's Blender needs the Gridwalk add-on installed
// and enabled (see docs/distributed.md).
//
// Each task runs
//     {blender} {blenderArgs} FILE.blend --python-expr SCRIPT
// where SCRIPT sets the render engine to GRIDWALK, renders the task's frames
// one by one (write_still: "Saved: ..." lines, as Flamenco expects) and leaves
// Blender with exit status 1, naming the frame, when Gridwalk reports an
// error. When the add-on is not registered, setting the engine fails and so
// does the task: Blender would otherwise render with another engine without a
// word (`-E GRIDWALK` with an unknown engine only prints a warning).

const JOB_TYPE = {
    label: "Gridwalk Render",
    description: "Render frames with the Gridwalk engine; a worker without the add-on fails the task",
    settings: [
        {
            key: "frames",
            type: "string",
            required: true,
            eval: "f'{C.scene.frame_start}-{C.scene.frame_end}'",
            evalInfo: { showLinkButton: true, description: "Scene frame range" },
            description: "Frames to render, e.g. '47', '1-30', '3, 5-10, 47-327'",
        },
        {
            key: "chunk_size",
            type: "int32",
            default: 1,
            description: "Frames per task (Blender starts once per task)",
            visible: "submission",
        },
        {
            key: "render_output_path",
            type: "string",
            subtype: "file_path",
            required: true,
            eval: "abspath(C.scene.render.filepath)",
            description: "Output path; '#' characters become the frame number (###### is added when there are none)",
            visible: "submission",
        },
        { key: "blendfile", type: "string", required: true, visible: "web", description: "The .blend file to render" },
    ],
};

function compileJob(job) {
    const settings = job.settings;
    let output = settings.render_output_path;
    if (!output.includes("#")) {
        output += "######";
    }
    for (const frames of frameChunks(settings.frames, settings.chunk_size)) {
        const last = frames[frames.length - 1];
        const name = last - frames[0] === frames.length - 1 && frames.length > 1 ? `${frames[0]}-${last}` : frames.join(",");
        const task = author.Task(`gridwalk-render-${name}`, "blender");
        task.addCommand(author.Command("blender-render", {
            exe: "{blender}",
            exeArgs: "{blenderArgs}",
            argsBefore: [],
            blendfile: settings.blendfile,
            args: ["--python-expr", renderScript(frames, output)],
        }));
        job.addTask(task);
    }
}

// "1-3, 7" -> [[1, 2], [3, 7]] for chunk size 2.
function frameChunks(text, size) {
    const frames = [];
    for (const part of String(text).split(",")) {
        const range = part.trim().match(/^(-?\d+)(?:(?:-|\.\.)(-?\d+))?$/);
        if (!range) {
            throw `frames: ${JSON.stringify(part.trim())} is not a frame or a range A-B`;
        }
        const first = parseInt(range[1], 10);
        const last = range[2] === undefined ? first : parseInt(range[2], 10);
        if (last < first) {
            throw `frames: the range ${part.trim()} ends before it starts`;
        }
        for (let f = first; f <= last; f++) {
            frames.push(f);
        }
    }
    const step = Math.max(1, parseInt(size, 10) || 1);
    const chunks = [];
    for (let i = 0; i < frames.length; i += step) {
        chunks.push(frames.slice(i, i + step));
    }
    return chunks;
}

// The Python that Blender runs for one task (JSON strings and lists are Python literals).
function renderScript(frames, output) {
    return [
        "import bpy, os, sys",
        "def gridwalk_fail(message):",
        "    print('GRIDWALK-FLAMENCO-ERROR ' + message)",
        "    sys.stdout.flush()",
        "    os._exit(1)",
        "scene = bpy.context.scene",
        "try:",
        "    scene.render.engine = 'GRIDWALK'",
        "except TypeError:",
        "    gridwalk_fail('the GRIDWALK render engine is not registered in Blender ' + bpy.app.version_string +",
        "                  ' on this worker: install and enable the Gridwalk add-on')",
        `for frame in ${JSON.stringify(frames)}:`,
        "    scene.frame_set(frame)",
        `    scene.render.filepath = ${JSON.stringify(output)}`,
        "    scene.render.filepath = scene.render.frame_path(frame=frame)   # write_still keeps '#' as it is",
        "    try:",
        "        bpy.ops.render.render(write_still=True)",
        "    except RuntimeError as exc:",
        "        gridwalk_fail('frame %d: %s' % (frame, exc))",
        "sys.stdout.flush()",
        "os._exit(0)",
    ].join("\n");
}
