// NimbusMetal: draws a Nimbus package's still frame into an MTKView, from the package alone:
// the passes, their order, files, bindings and targets from nimbus-package.json, each MSL file's
// buffer, texture and sampler indices (and sampler states) from its .json manifest, the uniform
// blocks' bytes from uniforms/*.json, the textures from textures/. It draws what the Vulkan host
// in Nimbus's repository draws: sun_light, then shadow, air, clouds and display, each into the
// target its `writes` names; a still frame neither upscales nor accumulates, so resolve is not
// drawn and display shows the clouds' target.
//
//     let view = MTKView(frame: frame, device: MTLCreateSystemDefaultDevice())
//     let clouds = try NimbusMetal(view: view, package: Bundle.main.url(forResource: "clouds", withExtension: nil)!)
//     view.delegate = clouds
//
// UNVERIFIED: no Apple compiler runs where Nimbus is built and tested (Linux): neither this file
// nor the MSL it loads has been compiled. The Vulkan host, which does the same steps, is checked
// against `nimbus render` there.
import Foundation
import Metal
import MetalKit

public enum NimbusMetalError: Error, CustomStringConvertible {
    case file(String, Error)
    case package(String)

    public var description: String {
        switch self {
        case let .file(path, error): return "\(path): \(error)"
        case let .package(why): return "the package: \(why)"
        }
    }
}

public final class NimbusMetal: NSObject, MTKViewDelegate {
    private let device: MTLDevice
    private let queue: MTLCommandQueue
    private let root: URL
    private let pair: PairEntry
    private var blocks: [String: MTLBuffer] = [:]
    private var blockBytes: [String: [UInt8]] = [:]
    private var offsets: [String: [String: Int]] = [:]
    private var textures: [String: MTLTexture] = [:]
    private var targets: [String: MTLTexture] = [:]
    private var passes: [Pass] = []

    /// One pass, ready to encode.
    private struct Pass {
        let entry: PassEntry
        let render: MTLRenderPipelineState?
        let compute: MTLComputePipelineState?
        /// (stage, kind, index, resource id, sampler) per binding of each stage.
        let slots: [(stage: String, kind: String, index: Int, id: String, sampler: MTLSamplerState?)]
        /// The buffer of runtime-sized arrays' byte sizes, and its index.
        let sizes: (index: Int, binding: String)?
    }

    public init(view: MTKView, package: URL, pair index: Int = 0) throws {
        guard let device = view.device, let queue = device.makeCommandQueue() else {
            throw NimbusMetalError.package("the view has no Metal device")
        }
        self.device = device
        self.queue = queue
        root = package
        let description: PackageFile = try NimbusMetal.json(package.appendingPathComponent("nimbus-package.json"))
        guard description.pairs.indices.contains(index) else {
            throw NimbusMetalError.package("it has \(description.pairs.count) pair(s), not a pair \(index)")
        }
        pair = description.pairs[index]
        if pair.scene_depth {
            throw NimbusMetalError.package("pair \(pair.pair) reads the engine's depth, which this host does not bind")
        }
        super.init()
        view.colorPixelFormat = .bgra8Unorm // display writes sRGB-encoded values: no second encoding
        view.framebufferOnly = true
        // The pair's block twice: as the host fills it (the kernel's input) and as the kernel
        // completes it (what the passes read).
        try loadBlock("pair_inputs", file: pair.uniforms)
        try loadBlock("pair", file: pair.uniforms)
        try loadBlock("resolve", file: "uniforms/resolve.json")
        try loadBlock("display", file: "uniforms/display.json")
        for t in description.textures {
            textures[t.name] = try loadTexture(t, halves: description.texel_halves)
        }
        passes = try pair.passes.filter { $0.pass != "resolve" }.map(makePass)
        if let atlas = pair.shadow_atlas { targets["shadow_atlas"] = makeTarget(atlas.width, atlas.height) }
        if let table = pair.air_table { targets["air_table"] = makeTarget(table.width, table.height) }
    }

    // MARK: loading

    private static func json<T: Decodable>(_ url: URL) throws -> T {
        do {
            return try JSONDecoder().decode(T.self, from: Data(contentsOf: url))
        } catch {
            throw NimbusMetalError.file(url.path, error)
        }
    }

    private func loadBlock(_ id: String, file: String) throws {
        let u: UniformFile = try NimbusMetal.json(root.appendingPathComponent(file))
        var bytes = [UInt8](repeating: 0, count: u.size)
        var hex = u.bytes_hex.makeIterator()
        for i in 0..<u.size {
            guard let a = hex.next(), let b = hex.next(), let byte = UInt8(String([a, b]), radix: 16) else {
                throw NimbusMetalError.package("\(file): bytes_hex is shorter than size \(u.size)")
            }
            bytes[i] = byte
        }
        blockBytes[id] = bytes
        offsets[id] = Dictionary(u.members.map { ($0.member, $0.offset) }, uniquingKeysWith: { a, _ in a })
        blocks[id] = device.makeBuffer(bytes: bytes, length: u.size, options: .storageModeShared)
    }

    /// Writes `values` (f32, little-endian) at `member` of block `id`.
    private func set(_ id: String, _ member: String, _ values: [Float]) {
        guard let buffer = blocks[id], let at = offsets[id]?[member] else { return }
        values.withUnsafeBytes { raw in
            buffer.contents().advanced(by: at).copyMemory(from: raw.baseAddress!, byteCount: raw.count)
        }
    }

    private func loadTexture(_ t: TextureEntry, halves: [UInt16]) throws -> MTLTexture {
        let url = root.appendingPathComponent(t.file)
        let width = t.size[0], height = t.size[1], depth = t.size.count > 2 ? t.size[2] : 1
        var texels: [UInt8]
        if t.dimension == "2d" {
            // PNG, rows top first: decoded without colour conversion.
            let loader = MTKTextureLoader(device: device)
            let png = try loader.newTexture(URL: url, options: [.SRGB: false, .textureStorageMode: MTLStorageMode.shared.rawValue])
            texels = [UInt8](repeating: 0, count: width * height * 4)
            png.getBytes(&texels, bytesPerRow: width * 4, from: MTLRegionMake2D(0, 0, width, height), mipmapLevel: 0)
            if png.pixelFormat == .bgra8Unorm {
                // The loader may keep the bytes in BGRA order: put them back as RGBA.
                for i in stride(from: 0, to: texels.count, by: 4) { texels.swapAt(i, i + 2) }
            }
        } else {
            texels = [UInt8](try Data(contentsOf: url))
        }
        // Each byte k becomes the half float the package lists: what Nimbus samples.
        let data = texels.map { halves[Int($0)] }
        // `r16float`: the file holds the one channel the shaders read, a byte a texel.
        let channels = t.format == "r16float" ? 1 : 4
        guard data.count == width * height * depth * channels else {
            throw NimbusMetalError.package("\(t.file): \(data.count) bytes, expected \(width * height * depth * channels)")
        }
        let d = MTLTextureDescriptor()
        d.textureType = t.dimension == "2d" ? .type2D : .type3D
        d.pixelFormat = channels == 1 ? .r16Float : .rgba16Float
        d.width = width
        d.height = height
        d.depth = depth
        d.usage = .shaderRead
        guard let texture = device.makeTexture(descriptor: d) else {
            throw NimbusMetalError.package("cannot make texture \(t.name)")
        }
        data.withUnsafeBytes { raw in
            texture.replace(region: MTLRegionMake3D(0, 0, 0, width, height, depth), mipmapLevel: 0, slice: 0,
                            withBytes: raw.baseAddress!, bytesPerRow: width * 2 * channels, bytesPerImage: width * height * 2 * channels)
        }
        return texture
    }

    private func makeTarget(_ width: Int, _ height: Int) -> MTLTexture? {
        let d = MTLTextureDescriptor.texture2DDescriptor(pixelFormat: .rgba16Float, width: width, height: height, mipmapped: false)
        d.usage = [.renderTarget, .shaderRead]
        d.storageMode = .private
        return device.makeTexture(descriptor: d)
    }

    private func samplerState(_ s: ManifestSampler?) -> MTLSamplerState? {
        let d = MTLSamplerDescriptor()
        let filter: MTLSamplerMinMagFilter = s?.filter == "nearest" ? .nearest : .linear
        d.minFilter = filter
        d.magFilter = filter
        let address: MTLSamplerAddressMode = s?.address_mode == "repeat" ? .repeat
            : s?.address_mode == "mirror-repeat" ? .mirrorRepeat : .clampToEdge
        d.sAddressMode = address
        d.tAddressMode = address
        d.rAddressMode = address
        return device.makeSamplerState(descriptor: d)
    }

    /// The index in `[[buffer(3)]]`.
    private static func index(_ attribute: String) -> Int? {
        Int(attribute.filter { $0.isNumber })
    }

    private func makePass(_ p: PassEntry) throws -> Pass {
        var functions: [String: MTLFunction] = [:]
        var slots: [(stage: String, kind: String, index: Int, id: String, sampler: MTLSamplerState?)] = []
        var sizes: (index: Int, binding: String)?
        for f in p.files {
            guard let entry = f.entry_point, let stage = f.stage, let manifestFile = f.manifest else { continue }
            let source = try String(contentsOf: root.appendingPathComponent(f.file), encoding: .utf8)
            let library = try device.makeLibrary(source: source, options: nil)
            guard let function = library.makeFunction(name: entry) else {
                throw NimbusMetalError.package("\(f.file) has no function \(entry)")
            }
            functions[stage] = function
            let manifest: Manifest = try NimbusMetal.json(root.appendingPathComponent(manifestFile))
            for b in manifest.bindings {
                guard let index = NimbusMetal.index(b.target_name),
                      let slot = p.bindings.first(where: { $0.group == b.group && $0.binding == b.binding }) else { continue }
                slots.append((stage, b.kind, index, slot.holds.id, b.kind == "sampler" ? samplerState(b.sampler) : nil))
            }
            if let s = f.buffer_sizes, let index = NimbusMetal.index(s.target_name), let member = s.members.first {
                sizes = (index, member.binding)
            }
        }
        if let kernel = functions["compute"] {
            return Pass(entry: p, render: nil, compute: try device.makeComputePipelineState(function: kernel), slots: slots, sizes: sizes)
        }
        let d = MTLRenderPipelineDescriptor()
        d.vertexFunction = functions["vertex"]
        d.fragmentFunction = functions["fragment"]
        d.colorAttachments[0].pixelFormat = p.writes == "screen" ? .bgra8Unorm : .rgba16Float
        return Pass(entry: p, render: try device.makeRenderPipelineState(descriptor: d), compute: nil, slots: slots, sizes: nil)
    }

    // MARK: drawing

    public func mtkView(_ view: MTKView, drawableSizeWillChange size: CGSize) {
        let (w, h) = (Int(size.width), Int(size.height))
        targets["clouds_hdr"] = makeTarget(w, h)
        for id in ["pair_inputs", "pair", "resolve", "display"] {
            set(id, "resolution", [Float(w), Float(h)])
        }
    }

    public func draw(in view: MTKView) {
        guard let drawable = view.currentDrawable, let commands = queue.makeCommandBuffer() else { return }
        if targets["clouds_hdr"] == nil { mtkView(view, drawableSizeWillChange: view.drawableSize) }
        // With no resolve drawn, display shows the clouds' target.
        targets["shown"] = targets["clouds_hdr"]
        for pass in passes {
            if let compute = pass.compute, let encoder = commands.makeComputeCommandEncoder() {
                encoder.setComputePipelineState(compute)
                for s in pass.slots {
                    // `pair_inputs` is the block as filled; `pair` is what the kernel writes.
                    if let buffer = blocks[s.id] { encoder.setBuffer(buffer, offset: 0, index: s.index) }
                }
                if let sizes = pass.sizes, let buffer = blocks[pass.entry.bindings.first { $0.name == sizes.binding }?.holds.id ?? ""] {
                    var length = UInt32(buffer.length)
                    encoder.setBytes(&length, length: 4, index: sizes.index)
                }
                encoder.dispatchThreadgroups(MTLSize(width: 1, height: 1, depth: 1), threadsPerThreadgroup: MTLSize(width: 1, height: 1, depth: 1))
                encoder.endEncoding()
                continue
            }
            guard let render = pass.render else { continue }
            let target = pass.entry.writes == "screen" ? drawable.texture : targets[pass.entry.writes] ?? nil
            let d = MTLRenderPassDescriptor()
            d.colorAttachments[0].texture = target
            d.colorAttachments[0].loadAction = .dontCare
            d.colorAttachments[0].storeAction = .store
            guard let encoder = commands.makeRenderCommandEncoder(descriptor: d) else { continue }
            encoder.setRenderPipelineState(render)
            encoder.setCullMode(.none)
            for s in pass.slots {
                switch (s.stage, s.kind) {
                case ("fragment", "uniform"), ("fragment", "storage"):
                    encoder.setFragmentBuffer(blocks[s.id], offset: 0, index: s.index)
                case ("vertex", "uniform"), ("vertex", "storage"):
                    encoder.setVertexBuffer(blocks[s.id], offset: 0, index: s.index)
                case ("fragment", "texture"):
                    encoder.setFragmentTexture(textures[s.id] ?? targets[s.id] ?? nil, index: s.index)
                case ("fragment", "sampler"):
                    encoder.setFragmentSamplerState(s.sampler, index: s.index)
                default:
                    break
                }
            }
            encoder.drawPrimitives(type: .triangle, vertexStart: 0, vertexCount: 3)
            encoder.endEncoding()
        }
        commands.present(drawable)
        commands.commit()
    }
}

// The parts of the package's JSON this host reads.
private struct PackageFile: Decodable { let textures: [TextureEntry]; let texel_halves: [UInt16]; let pairs: [PairEntry] }
private struct TextureEntry: Decodable { let name: String; let file: String; let dimension: String; let size: [Int]; let format: String }
private struct Size: Decodable { let width: Int; let height: Int }
private struct PairEntry: Decodable {
    let pair: String; let uniforms: String; let scene_depth: Bool
    let shadow_atlas: Size?; let air_table: Size?; let passes: [PassEntry]
}
private struct PassEntry: Decodable { let pass: String; let files: [ShaderFile]; let bindings: [BindingEntry]; let writes: String }
private struct ShaderFile: Decodable { let file: String; let entry_point: String?; let stage: String?; let manifest: String?; let buffer_sizes: BufferSizes? }
private struct BufferSizes: Decodable { let target_name: String; let members: [BufferSize] }
private struct BufferSize: Decodable { let member: String; let binding: String }
private struct Holds: Decodable { let id: String }
private struct BindingEntry: Decodable { let group: Int; let binding: Int; let name: String; let holds: Holds }
private struct Manifest: Decodable { let bindings: [ManifestBinding] }
private struct ManifestBinding: Decodable { let group: Int; let binding: Int; let kind: String; let target_name: String; let sampler: ManifestSampler? }
private struct ManifestSampler: Decodable { let address_mode: String; let filter: String }
private struct UniformFile: Decodable { let size: Int; let bytes_hex: String; let members: [Member] }
private struct Member: Decodable { let member: String; let offset: Int }
