// The identity of the code that computes a result: 16 hex digits that change
// whenever an engine, the front end, the number formats or a shipped config
// change (a hash of their sources, tools/model_identity.cmake), not only with
// the version number. Work dirs, shard and frame results record it, so that
// a result made by other code is never reused or merged (docs/BAD_INPUT.md,
// "Rules").
#pragma once

namespace raplas {
const char* model_identity();
}
