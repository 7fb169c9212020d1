"""The small scenes the model's Python checks simulate: the built-in scene,
and three shared scenes at 16x16 when ../shared/scenes is present. Each entry
is (name, raplas arguments selecting it)."""
import os


def small_scenes(root):
    shared = os.path.join(os.path.dirname(root), "shared", "scenes")
    scenes = [("builtin", ["--set", "image.width=24", "--set", "image.height=24", "--set", "groups.size=8",
                           "--set", "groups.shadow_size=8", "--set", "builtin_detail=2"])]
    if os.path.isdir(shared):
        for name in ("cornell", "bunny_small", "sportscar"):
            scenes.append((name, ["--scene", os.path.join(root, "scenes", name + ".toml"), "--set", "image.width=16",
                                  "--set", "image.height=16"]))
    else:
        print(f"note: {shared} missing: built-in scene only")
    return scenes
