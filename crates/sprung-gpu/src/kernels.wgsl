// The explicit step of sprung on the GPU (docs/gpu.md): one invocation a
// particle, in `real` (f32, or f64 where the adapter has it). The springs are gathered per particle over a compressed
// adjacency (each particle reads its own springs, in a fixed order), so
// nothing is added by two invocations at once and a run gives the same
// bits every time. The formulas are the engine's (docs/physics.md §1, §5):
// each kernel names the Rust function it follows.

// The kernels are written over `real`: f32, or f64 where the adapter has
// it; the prelude (precision.rs) defines it, `not_finite` and `cosine`.

// A collider, gathered from the uniform block's arrays.
struct Collider {
    // Plane: a point on it (xyz); sphere: the centre (xyz) and radius (w).
    point: vec4<real>,
    // Plane: the unit outward normal (xyz).
    normal: vec4<real>,
    // Projection: restitution, friction. Penalty: stiffness (N/m),
    // damping (N·s/m), friction.
    coefficients: vec4<real>,
    // x: shape (0 plane, 1 sphere); y: response (0 projection, 1 penalty).
    kind: vec4<u32>,
}

// The vectors of reals first, then the unsigned words, so that f32 and
// f64 lay out alike (Params::bytes). With the words first, lavapipe ran
// every kernel about ten times slower (measured: 2.2 against 0.22 ms a
// step of a 16² cloth; the cause lies in its handling of uniforms).
struct Params {
    // Gravity's acceleration (m/s², xyz) and the air drag's coefficient
    // (N·s/m, w).
    gravity: vec4<real>,
    // The (sub)step (s, x), and the blow-up limits squared (m², m²/s²; y,
    // z).
    limits: vec4<real>,
    // The wind's coefficient (N·s/m) or air density (kg/m³) (x), lift (y)
    // and the modes' amplitude (m/s, z); per mode, its direction, then its
    // wave vector (1/m).
    wind: vec4<real>,
    modes: array<vec4<real>, 16>,
    collider_point: array<vec4<real>, 64>,
    collider_normal: array<vec4<real>, 64>,
    collider_coefficients: array<vec4<real>, 64>,
    // Particles, colliders.
    count: u32,
    colliders: u32,
    // Workgroups along x of the particles' dispatch grid.
    row: u32,
    // Workgroups along x of the gas elements' grid.
    gas_row: u32,
    // Gas elements (padded), gas bodies, and the partial volumes (the
    // pressures follow them after the forces in `f`).
    elements: u32,
    gas_bodies: u32,
    parts: u32,
    // Where particle i's gas elements' range sits in `faces`: at
    // faces[element_first_at + i].
    element_first_at: u32,
    // Where particle i's wind elements' range sits in `faces`.
    wind_first_at: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
    // The wind's model (x: 0 none, 1 simple, 2 area) and turbulent modes
    // (y).
    wind_kind: vec4<u32>,
    // Per gas body, its first partial volume and how many (x, y), and the
    // next body's (z, w).
    gas: array<vec4<u32>, 24>,
    collider_kind: array<vec4<u32>, 64>,
}

// What changes from one force evaluation to the next: the time (s, x), the
// wind's gusting mean (m/s, xyz), each turbulent mode's phase φ - ω t
// (rad), and each gas body's nRT (J), four to a vector.
struct Stage {
    time: vec4<real>,
    wind: vec4<real>,
    phases: array<vec4<real>, 2>,
    nrt: array<vec4<real>, 12>,
}

// Eight storage buffers, WebGPU's least limit a shader stage: what the
// kernels read is packed into `adjacency` and `faces`, with each range
// given as positions in its own array.
@group(0) @binding(0) var<uniform> params: Params;
// Positions (m, xyz) with the inverse mass (1/kg, w).
@group(0) @binding(1) var<storage, read_write> x: array<vec4<real>>;
// Velocities (m/s, xyz) with the mass (kg, w).
@group(0) @binding(2) var<storage, read_write> v: array<vec4<real>>;
// The forces (N, xyz), `count` of them, then the gas sums (x): the
// partial volumes (m³, or m² in 2D), then each gas body's pressure (Pa).
@group(0) @binding(3) var<storage, read_write> f: array<vec4<real>>;
// Particle i's springs are the pairs (other end, spring) at
// adjacency[adjacency[i]..adjacency[i + 1]].
@group(0) @binding(4) var<storage, read> adjacency: array<u32>;
// Each spring's rest length (m, x), stiffness (N/m, y) and damping
// (N·s/m, z); then each body's wind scale (x).
@group(0) @binding(5) var<storage, read> constants: array<vec4<real>>;
// The gas elements first, four words each: its particles (a segment's
// third is 0xffffffff) and its gas body. Particle i's are listed at
// faces[faces[element_first_at + i]..faces[element_first_at + i + 1]],
// each as the position of its first word. The wind elements follow
// likewise (the fourth word: where its body's wind scale is in
// `constants`), from wind_first_at.
@group(0) @binding(6) var<storage, read> faces: array<u32>;
// [0]: steps taken; [1]: the first step whose state blew up (counted from
// 1), or 0xffffffff.
@group(0) @binding(7) var<storage, read_write> status: array<atomic<u32>>;
// The integrators' own state in four blocks of `count`: RK4's start
// position, start velocity, velocity sum and acceleration sum; Verlet's
// last move in the first.
@group(0) @binding(8) var<storage, read_write> scratch: array<vec4<real>>;
@group(1) @binding(0) var<uniform> stage: Stage;

// The element whose first word is faces[at].
fn face(at: u32) -> vec4<u32> {
    return vec4<u32>(faces[at], faces[at + 1u], faces[at + 2u], faces[at + 3u]);
}

// Whether a step that blew up has ended (then the state stays as it left
// it, for the engine's guard to read; the step itself runs to its end).
fn stopped() -> bool {
    return atomicLoad(&status[1]) <= atomicLoad(&status[0]);
}

// The invocation's particle, or `params.count` (none) once stopped.
fn particle(id: vec3<u32>) -> u32 {
    if stopped() {
        return params.count;
    }
    return id.x + id.y * params.row * 64u;
}

fn collider_at(c: u32) -> Collider {
    return Collider(
        params.collider_point[c],
        params.collider_normal[c],
        params.collider_coefficients[c],
        params.collider_kind[c],
    );
}

// Penalty colliders' force (colliders::penalty_force), static ones.
fn penalty(p: vec3<real>, u: vec3<real>) -> vec3<real> {
    var force = vec3<real>(0.0);
    for (var c = 0u; c < params.colliders; c++) {
        let collider = collider_at(c);
        if collider.kind.y != 1u {
            continue;
        }
        let near = distance_and_normal(collider, p);
        if near.w < 0.0 {
            let normal = near.xyz;
            let normal_speed = dot(u, normal);
            let k = collider.coefficients;
            let push = max(-k.x * near.w - k.y * normal_speed, 0.0);
            force += push * normal;
            if k.z > 0.0 {
                let sliding = u - normal_speed * normal;
                // colliders::FRICTION_REGULARISATION.
                let scale = sqrt(dot(sliding, sliding) + 0.01 * 0.01);
                force -= k.z * push * sliding / scale;
            }
        }
    }
    return force;
}

// Shape::distance_and_normal: the outward normal (xyz) and the signed
// distance (w, m).
fn distance_and_normal(collider: Collider, p: vec3<real>) -> vec4<real> {
    if collider.kind.x == 0u {
        let normal = collider.normal.xyz;
        return vec4<real>(normal, dot(p - collider.point.xyz, normal));
    }
    let offset = p - collider.point.xyz;
    let length = length(offset);
    if length > 0.0 {
        return vec4<real>(offset / length, length - collider.point.w);
    }
    return vec4<real>(0.0, 1.0, 0.0, -collider.point.w);
}

// The force on particle i (N): gravity, its springs (SpringForce, Hooke's
// law and a dashpot along each), the penalty colliders and air drag.
@compute @workgroup_size(64)
fn forces(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = particle(id);
    if i >= params.count {
        return;
    }
    let xi = x[i].xyz;
    let vi = v[i].xyz;
    var force = v[i].w * params.gravity.xyz;
    for (var e = adjacency[i]; e < adjacency[i + 1u]; e += 2u) {
        let other = adjacency[e];
        let spring = constants[adjacency[e + 1u]];
        let d = xi - x[other].xyz;
        let length = length(d);
        if length > 0.0 {
            let t = d / length;
            let s = spring.y * (length - spring.x) + spring.z * dot(vi - v[other].xyz, t);
            force -= s * t;
        }
    }
    let gas = params.element_first_at + i;
    for (var e = faces[gas]; e < faces[gas + 1u]; e++) {
        force += gas_push(face(faces[e]));
    }
    force += wind_force(i, xi, vi);
    force += penalty(xi, vi);
    force -= params.gravity.w * vi;
    f[i] = vec4<real>(force, 0.0);
}

const SEGMENT: u32 = 0xffffffffu;

// An element's share of its body's enclosed volume (surface::enclosed_volume,
// surface::enclosed_area): the divergence theorem over it.
fn volume_of(element: vec4<u32>) -> real {
    let a = x[element.x].xyz;
    let b = x[element.y].xyz;
    if element.z == SEGMENT {
        return 0.5 * (a.x + b.x) * (b.y - a.y);
    }
    let c = x[element.z].xyz;
    let area_normal = 0.5 * cross(b - a, c - a);
    return (a.x + b.x + c.x) / 3.0 * area_normal.x;
}

// The push of its body's gas on one corner of an element (GasPressure):
// the pressure times a third of the face's area normal, or half the
// segment's normal in 2D.
fn gas_push(element: vec4<u32>) -> vec3<real> {
    let pressure = f[params.count + params.parts + element.w].x;
    if pressure == 0.0 {
        return vec3<real>(0.0);
    }
    let a = x[element.x].xyz;
    let d = x[element.y].xyz - a;
    if element.z == SEGMENT {
        return 0.5 * pressure * vec3<real>(d.y, -d.x, 0.0);
    }
    return pressure / 3.0 * 0.5 * cross(d, x[element.z].xyz - a);
}

// The wind at `p` (WindField::velocity_at): the gusting mean and each
// turbulent mode.
fn wind_at(p: vec3<real>) -> vec3<real> {
    var wind = stage.wind.xyz;
    for (var m = 0u; m < params.wind_kind.y; m++) {
        let angle = dot(params.modes[2u * m + 1u].xyz, p) + stage.phases[m / 4u][m % 4u];
        wind += params.wind.z * cosine(angle) * params.modes[2u * m].xyz;
    }
    return wind;
}

fn normalize_or_zero(v: vec3<real>) -> vec3<real> {
    let length = length(v);
    if length > 0.0 {
        return v / length;
    }
    return vec3<real>(0.0);
}

// A wind element's area normal: half the cross product of a face's sides,
// or a segment's normal as long as it (a length per metre of depth).
fn area_normal(element: vec4<u32>) -> vec3<real> {
    let a = x[element.x].xyz;
    let d = x[element.y].xyz - a;
    if element.z == SEGMENT {
        return vec3<real>(d.y, -d.x, 0.0);
    }
    return 0.5 * cross(d, x[element.z].xyz - a);
}

// The wind's force on particle i (forces::Wind): the simple model's
// c ((w - v) · n) n with n its faces' mean unit normal, or its share of
// each of its faces' ρ A ((w - v) · n) n (with lift).
fn wind_force(i: u32, p: vec3<real>, u: vec3<real>) -> vec3<real> {
    let model = params.wind_kind.x;
    var force = vec3<real>(0.0);
    if model == 0u {
        return force;
    }
    var normals = vec3<real>(0.0);
    var scale: real = 1.0;
    let wind = params.wind_first_at + i;
    for (var e = faces[wind]; e < faces[wind + 1u]; e++) {
        let element = face(faces[e]);
        scale = constants[element.w].x;
        if model == 1u {
            normals += normalize_or_zero(area_normal(element));
            continue;
        }
        let normal = area_normal(element);
        let area = length(normal);
        if area == 0.0 {
            continue;
        }
        let n = normal / area;
        var corners: real = 3.0;
        var centroid = x[element.x].xyz + x[element.y].xyz;
        var mean_velocity = v[element.x].xyz + v[element.y].xyz;
        if element.z == SEGMENT {
            corners = 2.0;
        } else {
            centroid += x[element.z].xyz;
            mean_velocity += v[element.z].xyz;
        }
        centroid /= corners;
        mean_velocity /= corners;
        let relative = scale * wind_at(centroid) - mean_velocity;
        var f = params.wind.x * area * dot(relative, n) * n;
        if params.wind.y != 0.0 {
            let along = normalize_or_zero(relative);
            f += params.wind.y * (f - dot(f, along) * along);
        }
        force += f / corners;
    }
    if model == 1u {
        let n = normalize_or_zero(normals);
        if any(n != vec3<real>(0.0)) {
            force = params.wind.x * dot(scale * wind_at(p) - u, n) * n;
        }
    }
    return force;
}

var<workgroup> part: array<real, 64>;

// The elements' volumes summed 64 at a time, in a fixed order (a tree in
// the workgroup): one partial volume a workgroup, each of one body.
@compute @workgroup_size(64)
fn volume_parts(
    @builtin(global_invocation_id) id: vec3<u32>,
    @builtin(local_invocation_index) lane: u32,
    @builtin(workgroup_id) group: vec3<u32>,
) {
    let e = id.x + id.y * params.gas_row * 64u;
    var share: real = 0.0;
    if e < params.elements && !stopped() {
        share = volume_of(face(4u * e));
    }
    part[lane] = share;
    workgroupBarrier();
    for (var half = 32u; half > 0u; half >>= 1u) {
        if lane < half {
            part[lane] += part[lane + half];
        }
        workgroupBarrier();
    }
    let index = group.x + group.y * params.gas_row;
    if lane == 0u && index < params.parts {
        f[params.count + index].x = part[0];
    }
}

// Each gas body's volume (its partial volumes summed in order) and
// pressure nRT / V (forces::pressure; none where the volume is not
// positive).
@compute @workgroup_size(64)
fn pressures(@builtin(global_invocation_id) id: vec3<u32>) {
    let g = id.x;
    if g >= params.gas_bodies || stopped() {
        return;
    }
    let span = params.gas[g / 2u];
    var first = span.x;
    var parts = span.y;
    if g % 2u == 1u {
        first = span.z;
        parts = span.w;
    }
    var volume: real = 0.0;
    for (var k = 0u; k < parts; k++) {
        volume += f[params.count + first + k].x;
    }
    var pressure: real = 0.0;
    if volume > 0.0 {
        pressure = stage.nrt[g / 4u][g % 4u] / volume;
    }
    f[params.count + params.parts + g].x = pressure;
}

// Coulomb friction over one impulse (colliders::constraint::coulomb).
fn coulomb(tangential: vec3<real>, slowdown: real) -> vec3<real> {
    let speed = length(tangential);
    if speed > slowdown {
        return tangential * (1.0 - slowdown / speed);
    }
    return vec3<real>(0.0);
}

// The projection colliders (colliders::project, static ones) move a
// particle out and reflect its velocity; then the guard (World::guard)
// marks the step if the particle has blown up. `p`, `u` are updated.
fn collide_and_guard(i: u32, p: ptr<function, vec3<real>>, u: ptr<function, vec3<real>>) {
    if x[i].w != 0.0 {
        for (var c = 0u; c < params.colliders; c++) {
            let collider = collider_at(c);
            if collider.kind.y != 0u {
                continue;
            }
            let near = distance_and_normal(collider, *p);
            if near.w >= 0.0 {
                continue;
            }
            let normal = near.xyz;
            *p -= near.w * normal;
            let normal_speed = dot(*u, normal);
            if normal_speed >= 0.0 {
                continue;
            }
            let restitution = collider.coefficients.x;
            let friction = collider.coefficients.y;
            let tangential = *u - normal_speed * normal;
            let kept = coulomb(tangential, friction * (1.0 + restitution) * -normal_speed);
            *u = kept - restitution * normal_speed * normal;
        }
    }
    // Not finite, or past a limit.
    if not_finite(*p) || not_finite(*u)
        || dot(*p, *p) > params.limits.y
        || dot(*u, *u) > params.limits.z {
        atomicMin(&status[1], atomicLoad(&status[0]) + 1u);
    }
}

// Symplectic Euler (integrate::symplectic_euler): v += f w h, x += v h.
@compute @workgroup_size(64)
fn symplectic(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = particle(id);
    if i >= params.count {
        return;
    }
    let h = params.limits.x;
    var u = v[i].xyz + f[i].xyz * x[i].w * h;
    var p = x[i].xyz + u * h;
    collide_and_guard(i, &p, &u);
    x[i] = vec4<real>(p, x[i].w);
    v[i] = vec4<real>(u, v[i].w);
}

// Verlet's first step (integrate::verlet, bootstrap): the last move,
// x - x₋₁ = v h - a h² / 2. The kernels keep the move, not the previous
// position as the engine does: the same sums in exact arithmetic, without
// the cancellation of 2x - x₋₁ in f32.
@compute @workgroup_size(64)
fn verlet_start(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = particle(id);
    if i >= params.count {
        return;
    }
    let h = params.limits.x;
    let a = f[i].xyz * x[i].w;
    scratch[i] = vec4<real>(v[i].xyz * h - 0.5 * a * h * h, 0.0);
}

// Position Verlet with central velocities (integrate::verlet): the next
// move is the last plus a h², the velocity (x₊₁ - x₋₁) / 2h + a h. A
// collider that moves the particle or changes its velocity changes its
// move as the engine's bootstrap does at the next step.
@compute @workgroup_size(64)
fn verlet(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = particle(id);
    if i >= params.count {
        return;
    }
    let h = params.limits.x;
    let a = f[i].xyz * x[i].w;
    let last = scratch[i].xyz;
    var step_move = last + a * (h * h);
    let next = x[i].xyz + step_move;
    let written = (last + step_move) / (2.0 * h) + a * h;
    var p = next;
    var u = written;
    collide_and_guard(i, &p, &u);
    // The engine's previous position moves by (p - next) - (u - written) h,
    // so the move from it to p changes by (u - written) h.
    step_move += (u - written) * h;
    scratch[i] = vec4<real>(step_move, 0.0);
    x[i] = vec4<real>(p, x[i].w);
    v[i] = vec4<real>(u, v[i].w);
}

// RK4's start (integrate::rk4): the state kept, the sums cleared.
@compute @workgroup_size(64)
fn rk4_begin(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = particle(id);
    let n = params.count;
    if i >= n {
        return;
    }
    scratch[i] = x[i];
    scratch[n + i] = v[i];
    scratch[2u * n + i] = vec4<real>(0.0);
    scratch[3u * n + i] = vec4<real>(0.0);
}

// One stage of RK4 with its weight in the sums and the offset of the next
// trial state: x, v hold the trial state, f its force.
fn rk4_stage(i: u32, weight: real, next_offset: real) {
    let n = params.count;
    let h = params.limits.x;
    let stage_velocity = v[i].xyz;
    let stage_acceleration = f[i].xyz * x[i].w;
    scratch[2u * n + i] += vec4<real>(weight * stage_velocity, 0.0);
    scratch[3u * n + i] += vec4<real>(weight * stage_acceleration, 0.0);
    x[i] = vec4<real>(scratch[i].xyz + next_offset * h * stage_velocity, x[i].w);
    v[i] = vec4<real>(scratch[n + i].xyz + next_offset * h * stage_acceleration, v[i].w);
}

@compute @workgroup_size(64)
fn rk4_stage1(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = particle(id);
    if i < params.count {
        rk4_stage(i, 1.0, 0.5);
    }
}

@compute @workgroup_size(64)
fn rk4_stage2(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = particle(id);
    if i < params.count {
        rk4_stage(i, 2.0, 0.5);
    }
}

@compute @workgroup_size(64)
fn rk4_stage3(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = particle(id);
    if i < params.count {
        rk4_stage(i, 2.0, 1.0);
    }
}

// The last stage and the step: x = x₀ + h/6 Σ v, v = v₀ + h/6 Σ a.
@compute @workgroup_size(64)
fn rk4_end(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = particle(id);
    let n = params.count;
    if i >= n {
        return;
    }
    let sixth = params.limits.x / 6.0;
    let sum_v = scratch[2u * n + i].xyz + v[i].xyz;
    let sum_a = scratch[3u * n + i].xyz + f[i].xyz * x[i].w;
    var p = scratch[i].xyz + sixth * sum_v;
    var u = scratch[n + i].xyz + sixth * sum_a;
    collide_and_guard(i, &p, &u);
    x[i] = vec4<real>(p, x[i].w);
    v[i] = vec4<real>(u, v[i].w);
}

// The step's count, after its last kernel (the step that blew up is
// counted, none after it).
@compute @workgroup_size(1)
fn tick() {
    if !stopped() {
        atomicAdd(&status[0], 1u);
    }
}
