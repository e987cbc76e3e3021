// A test stand-in for the part of Unity.Mathematics the printed C# host functions call, with
// Unity.Mathematics' own signatures and f32 semantics (its source: github.com/Unity-Technologies/
// Unity.Mathematics), so that mono's compiler checks and runs the printed files without Unity.
// A function the printer starts to use and this file lacks fails the test's compile: add it here
// with Unity.Mathematics' signature, never change the printer to suit this file.
using System;

namespace Unity.Mathematics
{
    public struct float2
    {
        public float x, y;
        public float2(float x, float y) { this.x = x; this.y = y; }
        public float2(float v) { x = v; y = v; }
        public static float2 operator +(float2 a, float2 b) => new float2(a.x + b.x, a.y + b.y);
        public static float2 operator -(float2 a, float2 b) => new float2(a.x - b.x, a.y - b.y);
        public static float2 operator *(float2 a, float2 b) => new float2(a.x * b.x, a.y * b.y);
        public static float2 operator /(float2 a, float2 b) => new float2(a.x / b.x, a.y / b.y);
        public static float2 operator *(float2 a, float s) => new float2(a.x * s, a.y * s);
        public static float2 operator *(float s, float2 a) => new float2(s * a.x, s * a.y);
        public static float2 operator /(float2 a, float s) => new float2(a.x / s, a.y / s);
        public static float2 operator -(float2 a) => new float2(-a.x, -a.y);
    }

    public struct float3
    {
        public float x, y, z;
        public float3(float x, float y, float z) { this.x = x; this.y = y; this.z = z; }
        public float3(float v) { x = v; y = v; z = v; }
        public float3(float2 xy, float z) { x = xy.x; y = xy.y; this.z = z; }
        public static float3 operator +(float3 a, float3 b) => new float3(a.x + b.x, a.y + b.y, a.z + b.z);
        public static float3 operator -(float3 a, float3 b) => new float3(a.x - b.x, a.y - b.y, a.z - b.z);
        public static float3 operator *(float3 a, float3 b) => new float3(a.x * b.x, a.y * b.y, a.z * b.z);
        public static float3 operator *(float3 a, float s) => new float3(a.x * s, a.y * s, a.z * s);
        public static float3 operator *(float s, float3 a) => new float3(s * a.x, s * a.y, s * a.z);
        public static float3 operator /(float3 a, float s) => new float3(a.x / s, a.y / s, a.z / s);
        public static float3 operator -(float3 a) => new float3(-a.x, -a.y, -a.z);
    }

    public struct float4
    {
        public float x, y, z, w;
        public float4(float x, float y, float z, float w) { this.x = x; this.y = y; this.z = z; this.w = w; }
        public float4(float v) { x = v; y = v; z = v; w = v; }
        public static float4 operator +(float4 a, float4 b) => new float4(a.x + b.x, a.y + b.y, a.z + b.z, a.w + b.w);
        public static float4 operator -(float4 a, float4 b) => new float4(a.x - b.x, a.y - b.y, a.z - b.z, a.w - b.w);
        public static float4 operator *(float4 a, float s) => new float4(a.x * s, a.y * s, a.z * s, a.w * s);
        public static float4 operator -(float4 a) => new float4(-a.x, -a.y, -a.z, -a.w);
    }

    public static class math
    {
        public static float sin(float x) => (float)Math.Sin(x);
        public static float cos(float x) => (float)Math.Cos(x);
        public static float abs(float x) => Math.Abs(x);
        public static float4 abs(float4 v) => new float4(Math.Abs(v.x), Math.Abs(v.y), Math.Abs(v.z), Math.Abs(v.w));
        public static float max(float a, float b) => a > b ? a : b;
        public static float min(float a, float b) => a < b ? a : b;
        public static float ceil(float x) => (float)Math.Ceiling(x);
        public static float floor(float x) => (float)Math.Floor(x);
        public static float saturate(float x) => clamp(x, 0.0f, 1.0f);
        public static float clamp(float x, float a, float b) => max(a, min(b, x));
        public static float smoothstep(float a, float b, float x)
        {
            var t = saturate((x - a) / (b - a));
            return t * t * (3.0f - (2.0f * t));
        }
    }
}
