// NimbusClouds: draws a Nimbus package's clouds on a camera of Unity's built-in render pipeline
// with one command buffer, from the package alone. Put the package folder under
// Assets/StreamingAssets (its .hlsl, .shader and .compute files may also live under Assets, where
// Unity compiles them), add this component to the camera, and assign the `sun-light.compute`
// asset to `sunLight`. Needs Unity 2021.2 or later (GraphicsBuffer copies) and the
// com.unity.mathematics package (the printed host functions use it).
//
// Everything a formula decides comes from the package: the passes, their order, bindings and
// targets from nimbus-package.json; the uniform blocks' bytes and member offsets from
// uniforms/*.json; the frame sequence and the wind from NimbusFrame.cs and NimbusWind.cs, the
// C# twins Nimbus prints of its own shader functions; the sun's light and the shadow cascades
// from the sun_light kernel on the GPU. This file only moves data.
using System;
using System.Collections.Generic;
using System.IO;
using Unity.Mathematics;
using UnityEngine;
using UnityEngine.Rendering;

namespace Nimbus
{
    [RequireComponent(typeof(Camera))]
    public sealed class NimbusClouds : MonoBehaviour
    {
        [Tooltip("The package's folder, relative to Assets/StreamingAssets.")]
        public string package = "Nimbus";
        [Tooltip("Which of the package's genus × preset pairs to draw.")]
        public int pair;
        [Tooltip("The package's sun_light.compute asset.")]
        public ComputeShader sunLight;
        [Tooltip("The package's .shader assets, if Shader.Find cannot see them in a build.")]
        public Shader[] shaders = new Shader[0];
        public float sunElevation = 30f;
        public float sunAzimuth = 150f;
        [Tooltip("Wind near the ground: m/s, and where it blows from (degrees from north).")]
        public float windSpeed = 6f;
        public float windFrom = 260f;
        [Tooltip("The camera's height above the ground at the scene's origin (m).")]
        public float groundOffset = 2f;
        public bool upscale = true;

        PackageFile description;
        PairEntry chosen;
        readonly Dictionary<string, Block> blocks = new Dictionary<string, Block>();
        readonly Dictionary<string, Texture> textures = new Dictionary<string, Texture>();
        readonly Dictionary<string, Material> materials = new Dictionary<string, Material>();
        GraphicsBuffer completed;
        RenderTexture shadowAtlas, airTable, cloudsHdr, historyA, historyB;
        CommandBuffer commands;
        Camera view;
        uint frameIndex;
        float4x4 previousViewProjection;
        float4 previousDrift;

        void OnEnable()
        {
            view = GetComponent<Camera>();
            string root = Path.Combine(Application.streamingAssetsPath, package);
            description = JsonUtility.FromJson<PackageFile>(File.ReadAllText(Path.Combine(root, "nimbus-package.json")));
            if (pair < 0 || pair >= description.pairs.Length)
            {
                Debug.LogError($"NimbusClouds: the package has {description.pairs.Length} pair(s), not a pair {pair}");
                enabled = false;
                return;
            }
            chosen = description.pairs[pair];
            if (chosen.scene_depth)
            {
                Debug.LogError($"NimbusClouds: pair {chosen.pair} reads the engine's depth, which this host does not bind; emit a package without scene depth");
                enabled = false;
                return;
            }
            if (sunLight == null && Array.Exists(chosen.passes, p => p.pass == "sun_light"))
            {
                Debug.LogError("NimbusClouds: assign the package's sun-light.compute to Sun Light");
                enabled = false;
                return;
            }
            blocks["pair_inputs"] = Block.Load(Path.Combine(root, chosen.uniforms));
            blocks["pair"] = Block.Load(Path.Combine(root, chosen.uniforms));
            blocks["resolve"] = Block.Load(Path.Combine(root, "uniforms/resolve.json"));
            blocks["display"] = Block.Load(Path.Combine(root, "uniforms/display.json"));
            // The kernel writes the completed block as words; Direct3D 11 binds no buffer as both
            // a UAV and a constant buffer, so it is copied into the `pair` block after each run.
            completed = new GraphicsBuffer(GraphicsBuffer.Target.Structured | GraphicsBuffer.Target.CopySource, blocks["pair"].Bytes.Length / 4, 4);
            foreach (var t in description.textures)
            {
                textures[t.name] = LoadTexture(root, t, description.texel_halves);
            }
            if (chosen.shadow_atlas.width > 0)
            {
                shadowAtlas = Target(chosen.shadow_atlas.width, chosen.shadow_atlas.height);
            }
            if (chosen.air_table.width > 0)
            {
                airTable = Target(chosen.air_table.width, chosen.air_table.height);
            }
            foreach (var p in chosen.passes)
            {
                if (p.pass == "sun_light")
                {
                    continue;
                }
                Shader shader = Shader.Find("Nimbus/" + p.shader);
                foreach (var s in shaders)
                {
                    if (s != null && s.name == "Nimbus/" + p.shader)
                    {
                        shader = s;
                    }
                }
                if (shader == null)
                {
                    Debug.LogError($"NimbusClouds: no shader Nimbus/{p.shader}: import {p.shader}.shader and its .hlsl");
                    enabled = false;
                    return;
                }
                materials[p.shader] = new Material(shader);
            }
            // Rows: OpenGL-style targets are bottom-up, so the display pass turns the picture.
            blocks["display"].Set("flip_y", SystemInfo.graphicsUVStartsAtTop ? 0f : 1f);
            commands = new CommandBuffer { name = "Nimbus clouds" };
            view.AddCommandBuffer(CameraEvent.BeforeImageEffects, commands);
        }

        void OnDisable()
        {
            if (view != null && commands != null)
            {
                view.RemoveCommandBuffer(CameraEvent.BeforeImageEffects, commands);
            }
            commands?.Release();
            completed?.Release();
            foreach (var b in blocks.Values)
            {
                b.Release();
            }
            blocks.Clear();
            foreach (var rt in new[] { shadowAtlas, airTable, cloudsHdr, historyA, historyB })
            {
                if (rt != null)
                {
                    rt.Release();
                }
            }
            cloudsHdr = historyA = historyB = null;
        }

        static RenderTexture Target(int width, int height)
        {
            var rt = new RenderTexture(width, height, 0, RenderTextureFormat.ARGBHalf, RenderTextureReadWrite.Linear);
            rt.Create();
            return rt;
        }

        void OnPreRender()
        {
            if (commands == null)
            {
                return;
            }
            int width = view.pixelWidth, height = view.pixelHeight;
            uint upscaled = upscale ? 1u : 0u;
            var low = NimbusFrame.resolve_frame(0u, upscaled, 0u, new float4(0f), new float4(0f), 0f, new float2(width, height)).low_resolution;
            if (cloudsHdr == null || cloudsHdr.width != (int)low.x || historyA.width != width || historyA.height != height)
            {
                foreach (var rt in new[] { cloudsHdr, historyA, historyB })
                {
                    if (rt != null)
                    {
                        rt.Release();
                    }
                }
                cloudsHdr = Target((int)low.x, (int)low.y);
                historyA = Target(width, height);
                historyB = Target(width, height);
                frameIndex = 0;
            }
            UpdateBlocks(width, height, upscaled);
            Record();
            frameIndex++;
            (historyA, historyB) = (historyB, historyA);
        }

        void UpdateBlocks(int width, int height, uint upscaled)
        {
            var inputs = blocks["pair_inputs"];
            // Nimbus's local frame: x east, y up, z south; Unity's z points north.
            float4x4 flip = float4x4.Scale(1f, 1f, -1f);
            float4x4 rotation = (float4x4)view.worldToCameraMatrix;
            rotation.c3 = new float4(0f, 0f, 0f, 1f);
            float4x4 viewProjection = math.mul((float4x4)view.projectionMatrix, math.mul(rotation, flip));
            Vector3 position = view.transform.position;
            float altitude = math.max(position.y + groundOffset, 0f);
            float seconds = Time.time;
            float2 ground = NimbusWind.wind_velocity(windSpeed, windFrom);
            float4 drift = NimbusWind.wind_drift(ground, ground, seconds);
            var frame = NimbusFrame.cloud_frame(frameIndex, 0u, upscaled);
            inputs.Set("light.sun_direction", NimbusSun.sun_direction(sunElevation, sunAzimuth));
            inputs.Set("camera_altitude", altitude);
            inputs.Set("camera_offset", new float3(position.x, 0f, -position.z));
            inputs.Set("inverse_view_projection", math.inverse(viewProjection));
            inputs.Set("media.wind_drift", drift.xy);
            inputs.Set("media.wind_shear_drift", drift.zw);
            inputs.Set("resolution", new float2(width, height));
            inputs.Set("pixel_offset", frame.pixel_offset);
            inputs.Set("pixel_scale", frame.pixel_scale);
            inputs.Set("subpixel", frame.subpixel);
            inputs.Set("frame", frame.frame);
            inputs.Set("jitter", frame.jitter);
            inputs.Upload();
            var march = inputs.Floats("march.min_height", 2);
            float facing = NimbusWind.facing_altitude(altitude, march[0], march[1]);
            uint moved = math.any(viewProjection.c0 != previousViewProjection.c0) || math.any(viewProjection.c1 != previousViewProjection.c1)
                || math.any(viewProjection.c2 != previousViewProjection.c2) || math.any(viewProjection.c3 != previousViewProjection.c3) ? 1u : 0u;
            var r = NimbusFrame.resolve_frame(frameIndex, upscaled, moved, drift, previousDrift, facing, new float2(width, height));
            var resolve = blocks["resolve"];
            resolve.Set("inverse_view_projection", math.inverse(viewProjection));
            resolve.Set("previous_view_projection", frameIndex == 0 ? viewProjection : previousViewProjection);
            resolve.Set("cloud_shift", r.cloud_shift);
            resolve.Set("cloud_altitude", facing);
            resolve.Set("camera_altitude", altitude);
            resolve.Set("resolution", new float2(width, height));
            resolve.Set("low_resolution", r.low_resolution);
            resolve.Set("pixel_offset", r.pixel_offset);
            resolve.Set("pixel_scale", r.pixel_scale);
            resolve.Set("current_weight", r.current_weight);
            resolve.Set("variance_gamma", r.variance_gamma);
            resolve.Set("history_valid", r.history_valid);
            resolve.Upload();
            blocks["display"].Set("resolution", new float2(width, height));
            blocks["display"].Upload();
            previousViewProjection = viewProjection;
            previousDrift = drift;
        }

        /// The target a pass draws into, by the package's `writes`.
        RenderTargetIdentifier Output(string writes)
        {
            switch (writes)
            {
                case "shadow_atlas": return shadowAtlas;
                case "air_table": return airTable;
                case "clouds_hdr": return cloudsHdr;
                case "history": return historyA;
                default: return BuiltinRenderTextureType.CameraTarget;
            }
        }

        /// What a binding's `holds.id` names, for the textures and targets.
        Texture Resource(string id)
        {
            switch (id)
            {
                case "shadow_atlas": return shadowAtlas;
                case "air_table": return airTable;
                case "clouds_hdr": return cloudsHdr;
                case "history_read": return historyB;
                // The picture the display pass shows: what resolve wrote, or the clouds.
                case "shown": return Array.Exists(chosen.passes, p => p.pass == "resolve") ? historyA : cloudsHdr;
                default: return textures.TryGetValue(id, out var t) ? t : null;
            }
        }

        void Record()
        {
            commands.Clear();
            foreach (var p in chosen.passes)
            {
                if (p.pass == "sun_light")
                {
                    int kernel = sunLight.FindKernel(p.entry_points.compute);
                    foreach (var b in p.bindings)
                    {
                        if (b.holds.id == "pair_inputs")
                        {
                            var inputs = blocks["pair_inputs"];
                            commands.SetComputeConstantBufferParam(sunLight, b.Name, inputs.Buffer, 0, inputs.Bytes.Length);
                        }
                        else if (b.holds.id == "pair")
                        {
                            commands.SetComputeBufferParam(sunLight, kernel, b.Name, completed);
                        }
                    }
                    commands.DispatchCompute(sunLight, kernel, 1, 1, 1);
                    commands.CopyBuffer(completed, blocks["pair"].Buffer);
                    continue;
                }
                foreach (var b in p.bindings)
                {
                    if (b.kind == "uniform")
                    {
                        var block = blocks[b.holds.id];
                        commands.SetGlobalConstantBuffer(block.Buffer, b.Name, 0, block.Bytes.Length);
                    }
                    else if (b.kind == "texture")
                    {
                        commands.SetGlobalTexture(b.Name, Resource(b.holds.id));
                    }
                    // Samplers are inline sampler states: their HLSL names say filter and wrap.
                }
                commands.SetRenderTarget(Output(p.writes));
                commands.DrawProcedural(Matrix4x4.identity, materials[p.shader], 0, MeshTopology.Triangles, 3);
            }
        }

        static Texture LoadTexture(string root, TextureEntry t, ushort[] halves)
        {
            byte[] file = File.ReadAllBytes(Path.Combine(root, t.file));
            int width = t.size[0], height = t.size[1], depth = t.size.Length > 2 ? t.size[2] : 1;
            byte[] texels = file;
            if (t.dimension == "2d")
            {
                // PNG rows top first, as WebGPU uploads them; Unity's image loader stores them
                // bottom first, so the rows are put back.
                var png = new Texture2D(2, 2, TextureFormat.RGBA32, false, true);
                png.LoadImage(file, false);
                Color32[] pixels = png.GetPixels32();
                texels = new byte[width * height * 4];
                for (int y = 0; y < height; y++)
                {
                    for (int x = 0; x < width; x++)
                    {
                        Color32 c = pixels[(height - 1 - y) * width + x];
                        int i = (y * width + x) * 4;
                        texels[i] = c.r; texels[i + 1] = c.g; texels[i + 2] = c.b; texels[i + 3] = c.a;
                    }
                }
                Destroy(png);
            }
            // Each byte k becomes the half float the package lists for it: what Nimbus samples.
            var data = new ushort[texels.Length];
            for (int i = 0; i < texels.Length; i++)
            {
                data[i] = halves[texels[i]];
            }
            Texture texture;
            if (t.dimension == "2d")
            {
                var t2 = new Texture2D(width, height, TextureFormat.RGBAHalf, false, true);
                t2.SetPixelData(data, 0);
                t2.Apply(false, true);
                texture = t2;
            }
            else
            {
                // `r16float`: the file holds the one channel the shaders read, a byte a texel.
                var format = t.format == "r16float" ? TextureFormat.RHalf : TextureFormat.RGBAHalf;
                int channels = t.format == "r16float" ? 1 : 4;
                if (data.Length != width * height * depth * channels)
                {
                    throw new InvalidDataException($"{t.file}: {data.Length} bytes, expected {width * height * depth * channels}");
                }
                var t3 = new Texture3D(width, height, depth, format, false);
                t3.SetPixelData(data, 0);
                t3.Apply(false, true);
                texture = t3;
            }
            texture.wrapMode = t.address_mode == "repeat" ? TextureWrapMode.Repeat : t.address_mode == "mirror-repeat" ? TextureWrapMode.Mirror : TextureWrapMode.Clamp;
            texture.filterMode = t.filter == "linear" ? FilterMode.Bilinear : FilterMode.Point;
            return texture;
        }

        /// A uniform block: its bytes, its members' offsets (from the package's uniform file) and
        /// the constant buffer it is uploaded to.
        sealed class Block
        {
            public byte[] Bytes;
            public GraphicsBuffer Buffer;
            readonly Dictionary<string, int> offsets = new Dictionary<string, int>();

            public static Block Load(string file)
            {
                var u = JsonUtility.FromJson<UniformFile>(File.ReadAllText(file));
                var block = new Block { Bytes = new byte[u.size] };
                for (int i = 0; i < u.size; i++)
                {
                    block.Bytes[i] = Convert.ToByte(u.bytes_hex.Substring(2 * i, 2), 16);
                }
                foreach (var m in u.members)
                {
                    block.offsets[m.member] = m.offset;
                }
                block.Buffer = new GraphicsBuffer(GraphicsBuffer.Target.Constant | GraphicsBuffer.Target.CopyDestination, u.size / 16, 16);
                block.Upload();
                return block;
            }

            int At(string member)
            {
                if (!offsets.TryGetValue(member, out int offset))
                {
                    throw new ArgumentException($"the uniform block has no member `{member}`");
                }
                return offset;
            }

            void Put(string member, params float[] values)
            {
                int at = At(member);
                for (int i = 0; i < values.Length; i++)
                {
                    System.Buffer.BlockCopy(BitConverter.GetBytes(values[i]), 0, Bytes, at + 4 * i, 4);
                }
            }

            public void Set(string member, float v) => Put(member, v);
            public void Set(string member, uint v) => System.Buffer.BlockCopy(BitConverter.GetBytes(v), 0, Bytes, At(member), 4);
            public void Set(string member, float2 v) => Put(member, v.x, v.y);
            public void Set(string member, float3 v) => Put(member, v.x, v.y, v.z);
            // Column-major, one 16-byte column after another, as WGSL and HLSL's row_major read it.
            public void Set(string member, float4x4 m) => Put(member,
                m.c0.x, m.c0.y, m.c0.z, m.c0.w, m.c1.x, m.c1.y, m.c1.z, m.c1.w,
                m.c2.x, m.c2.y, m.c2.z, m.c2.w, m.c3.x, m.c3.y, m.c3.z, m.c3.w);

            public float[] Floats(string member, int count)
            {
                var values = new float[count];
                for (int i = 0; i < count; i++)
                {
                    values[i] = BitConverter.ToSingle(Bytes, At(member) + 4 * i);
                }
                return values;
            }

            public void Upload() => Buffer.SetData(Bytes);
            public void Release() => Buffer?.Release();
        }

        // The parts of nimbus-package.json and uniforms/*.json this host reads (JsonUtility
        // fills fields by their JSON names and ignores the rest).
#pragma warning disable 0649
        [Serializable] sealed class PackageFile { public TextureEntry[] textures; public ushort[] texel_halves; public PairEntry[] pairs; }
        [Serializable] sealed class TextureEntry { public string name; public string file; public string dimension; public int[] size; public string format; public string address_mode; public string filter; }
        [Serializable] sealed class PairEntry { public string pair; public string uniforms; public bool scene_depth; public Size shadow_atlas; public Size air_table; public PassEntry[] passes; }
        [Serializable] sealed class Size { public int width; public int height; }
        [Serializable] sealed class PassEntry { public string pass; public string shader; public EntryPoints entry_points; public BindingEntry[] bindings; public string writes; }
        [Serializable] sealed class EntryPoints { public string vertex; public string fragment; public string compute; }
        [Serializable] sealed class Holds { public string id; }
        [Serializable] sealed class NameInFile { public string stage; public string name; }
        [Serializable]
        sealed class BindingEntry
        {
            public int binding; public string name; public string kind; public Holds holds; public NameInFile[] in_files;
            /// The HLSL name (`name : register(..)` in the file's terms).
            public string Name => in_files.Length > 0 ? in_files[0].name.Split(' ')[0] : name;
        }
        [Serializable] sealed class UniformFile { public int size; public string bytes_hex; public Member[] members; }
        [Serializable] sealed class Member { public string member; public int offset; }
#pragma warning restore 0649
    }
}
