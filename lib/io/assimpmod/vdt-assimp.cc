/*
 * vdt-assimp.cc - vdt-assimp.so (assimpmod.h), the extern "C" face of
 * Assimp for skeletal animations:
 * DirectX .x, FBX, glTF 2 (.gltf, .glb), COLLADA, Valve SMD, IQM,
 * MilkShape 3D and Blitz3D files whose meshes are skinned to bones that
 * an animation moves. Each frame is baked here, in the way every engine
 * draws such a model (linear blend skinning):
 *
 *   p_t = sum over the vertex's bones b of  w_b * G_t(b) * O_b * p
 *
 * with G_t(b) the bone node's global transform at the frame's time (the
 * animation's channels, interpolated: positions and scalings linearly,
 * rotations by slerp; a node without a channel keeps its own transform)
 * and O_b the bone's offset matrix (mesh space to bone space at bind
 * time). A mesh without bones moves with its node. The frames are the
 * key times of one animation (the first that moves a node, or the one
 * asked for by name or number), every channel's together, in order, or
 * frames evenly spaced in time at a rate asked for (a model without an
 * animation is one frame, as posed); the meshes of every node are joined
 * into one, so that all frames share one connectivity.
 * Morph-target (blend shape) animation is not read.
 *
 * Assimp is reached through its C interface (cimport.h); what it cannot
 * read it says in aiGetErrorString, which becomes the message.
 */
#include <assimp/cimport.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <new>
#include <string>
#include <vector>

extern "C" {
#include "../assimpmod.h"
#include "../modcxx.h"
}

namespace {

/* A mesh of triangles where a node puts it, and the node of each of its
 * bones (the mesh's own node for a bone that names none), found once. */
struct Instance {
	const aiMesh *mesh;
	const aiNode *node;
	std::vector<const aiNode *> bones;
};

/* The instances under n, in node order. Indices need no check here:
 * aiProcess_ValidateDataStructure refuses a node's mesh, a face's vertex
 * or a weight's vertex out of range. */
void
collect(const aiScene *s, const aiNode *n, std::vector<Instance> &out)
{
	for (unsigned i = 0; i < n->mNumMeshes; i++) {
		const aiMesh *me = s->mMeshes[n->mMeshes[i]];
		if (!(me->mPrimitiveTypes & aiPrimitiveType_TRIANGLE))
			continue;
		out.push_back({me, n, {}});
		for (unsigned b = 0; b < me->mNumBones; b++) {
			const aiNode *bn = s->mRootNode->FindNode(me->mBones[b]->mName);
			out.back().bones.push_back(bn ? bn : n);
		}
	}
	for (unsigned i = 0; i < n->mNumChildren; i++)
		collect(s, n->mChildren[i], out);
}

template <class K>
unsigned
key_before(const K *keys, unsigned n, double t)
{
	/* the last key at or before t (0 if none) */
	unsigned lo = 0, hi = n;
	while (hi - lo > 1) {
		unsigned mid = (lo + hi) / 2;
		if (keys[mid].mTime <= t)
			lo = mid;
		else
			hi = mid;
	}
	return lo;
}

/* The value of keys k[0..n) at time t: the key's at or before the first,
 * after the last and on a key, else mix of the two around t and how far
 * along; dflt without keys. */
template <class K, class V, class Mix>
V
value_at(const K *k, unsigned n, double t, const V &dflt, Mix mix)
{
	if (n == 0)
		return dflt;
	unsigned i = key_before(k, n, t);
	if (i + 1 >= n || t <= k[i].mTime)
		return k[i].mValue;
	return mix(k[i].mValue, k[i + 1].mValue,
	           (ai_real)((t - k[i].mTime) / (k[i + 1].mTime - k[i].mTime)));
}

aiVector3D
vector_at(const aiVectorKey *k, unsigned n, double t, const aiVector3D &dflt)
{
	return value_at(k, n, t, dflt, [](const aiVector3D &a, const aiVector3D &b, ai_real f) {
		return a + (b - a) * f;
	});
}

aiQuaternion
rotation_at(const aiQuatKey *k, unsigned n, double t, const aiQuaternion &dflt)
{
	return value_at(k, n, t, dflt, [](const aiQuaternion &a, const aiQuaternion &b, ai_real f) {
		aiQuaternion q;
		aiQuaternion::Interpolate(q, a, b, f);
		return q.Normalize();
	});
}

/* Every node's global transform at time t of the animation whose channels
 * chan holds (none: as posed), by node. */
void
globals(const aiNode *n, const aiMatrix4x4 &parent,
        const std::map<const aiNode *, const aiNodeAnim *> &chan, double t,
        std::map<const aiNode *, aiMatrix4x4> &out)
{
	aiMatrix4x4 local = n->mTransformation;
	auto it = chan.find(n);
	if (it != chan.end()) {
		const aiNodeAnim *c = it->second;
		aiVector3D s0, p0;
		aiQuaternion r0;
		n->mTransformation.Decompose(s0, r0, p0);
		aiVector3D p = vector_at(c->mPositionKeys, c->mNumPositionKeys, t, p0);
		aiQuaternion r = rotation_at(c->mRotationKeys, c->mNumRotationKeys, t, r0);
		aiVector3D s = vector_at(c->mScalingKeys, c->mNumScalingKeys, t, s0);
		aiMatrix4x4 ms, mt;
		aiMatrix4x4::Scaling(s, ms);
		aiMatrix4x4::Translation(p, mt);
		local = mt * aiMatrix4x4(r.GetMatrix()) * ms;
	}
	aiMatrix4x4 g = parent * local;
	out[n] = g;
	for (unsigned i = 0; i < n->mNumChildren; i++)
		globals(n->mChildren[i], g, chan, t, out);
}

/* The animation of s that bo names (NULL in *a if s has none and bo names
 * none): 0 or a status. */
int
pick(const struct vdt_host *host, const aiScene *s, const struct vdt_bake_opts *bo,
     const aiAnimation **a, struct vdt_err *err)
{
	const char *want = bo ? bo->animation : nullptr;
	char *end;

	*a = nullptr;
	if (want == nullptr) {
		for (unsigned i = 0; i < s->mNumAnimations && !*a; i++)
			if (s->mAnimations[i]->mNumChannels > 0)
				*a = s->mAnimations[i];
		return 0;
	}
	for (unsigned i = 0; i < s->mNumAnimations; i++)
		if (strcmp(s->mAnimations[i]->mName.C_Str(), want) == 0) {
			*a = s->mAnimations[i];
			break;
		}
	errno = 0;
	unsigned long k = strtoul(want, &end, 10);
	if (*a == nullptr && *want >= '0' && *want <= '9' && *end == '\0' && errno == 0 &&
	    k < s->mNumAnimations)
		*a = s->mAnimations[k];
	if (*a == nullptr) {
		std::string names;
		for (unsigned i = 0; i < s->mNumAnimations && names.size() < 200; i++)
			names += std::string(i ? ", " : "") + std::to_string(i) + " '" +
			         s->mAnimations[i]->mName.C_Str() + "'";
		return host->err_set(err, VDT_EINVAL, "has no animation '%s' (%u: %s)", want,
		                   s->mNumAnimations, s->mNumAnimations ? names.c_str() : "none");
	}
	if ((*a)->mNumChannels == 0)
		return host->err_set(err, VDT_EINVAL, "animation '%s' moves no bone", want);
	return 0;
}

/* Frames of s's animation (pick) into *m and *fr (see the top of this
 * file); 0 or a status, with *m and *fr maybe half filled. */
int
bake(const struct vdt_host *host, const aiScene *s, const struct vdt_bake_opts *bo,
     struct vdt_mesh *m, struct vdt_frames *fr, struct vdt_err *err)
{
	/* Assimp stands a skeleton without a mesh in for the mesh. */
	if (s->mFlags & AI_SCENE_FLAGS_INCOMPLETE)
		return host->err_set(err, VDT_EINVAL, "has no mesh");
	std::vector<Instance> inst;
	if (s->mRootNode)
		collect(s, s->mRootNode, inst);
	size_t nv = 0, nt = 0;
	for (const Instance &i : inst) {
		nv += i.mesh->mNumVertices;
		for (unsigned f = 0; f < i.mesh->mNumFaces; f++)
			nt += i.mesh->mFaces[f].mNumIndices == 3;
	}
	if (nt == 0)
		return host->err_set(err, VDT_EINVAL, "has no triangles");
	if (nv > UINT32_MAX)
		return host->err_set(err, VDT_EINVAL, "has %zu vertices, more than 2^32", nv);
	const aiAnimation *a;
	int rc;
	if ((rc = pick(host, s, bo, &a, err)) != 0)
		return rc;
	std::map<const aiNode *, const aiNodeAnim *> chan;
	std::vector<double> times;
	if (a == nullptr) /* a still model: one frame, as the file poses it */
		times.push_back(0);
	for (unsigned c = 0; a != nullptr && c < a->mNumChannels; c++) {
		const aiNodeAnim *na = a->mChannels[c];
		const aiNode *node = s->mRootNode->FindNode(na->mNodeName);
		if (node == nullptr)
			continue;
		chan[node] = na;
		for (unsigned k = 0; k < na->mNumPositionKeys; k++)
			times.push_back(na->mPositionKeys[k].mTime);
		for (unsigned k = 0; k < na->mNumRotationKeys; k++)
			times.push_back(na->mRotationKeys[k].mTime);
		for (unsigned k = 0; k < na->mNumScalingKeys; k++)
			times.push_back(na->mScalingKeys[k].mTime);
	}
	for (double t : times)
		if (!std::isfinite(t))
			return host->err_set(err, VDT_EINVAL, "animation '%s' has a key at a non-finite time",
			                   a->mName.C_Str());
	std::sort(times.begin(), times.end());
	times.erase(std::unique(times.begin(), times.end()), times.end());
	if (times.empty()) /* channels of nodes that are not there */
		return host->err_set(err, VDT_EINVAL, "animation '%s' moves no node of the model",
		                   a->mName.C_Str());
	if (a != nullptr && bo != nullptr && bo->fps > 0) {
		/* Evenly in time instead; a file that does not say its rate is
		 * taken at Assimp's default, 25 ticks a second. */
		double tps = a->mTicksPerSecond > 0 ? a->mTicksPerSecond : 25;
		double t0 = times.front(), span = times.back() - t0, step = tps / bo->fps;
		double n = std::floor(span / step + 1e-9) + 1;
		if (!(n <= 1e6))
			return host->err_set(err, VDT_EINVAL,
			                   "%g frames a second of animation '%s' make %.3g frames, "
			                   "more than a million",
			                   bo->fps, a->mName.C_Str(), n);
		times.resize((size_t)n);
		for (size_t i = 0; i < times.size(); i++)
			times[i] = t0 + (double)i * step;
	}
	if ((rc = host->mesh_alloc(m, nv, nt, 0, err)) != 0 ||
	    (rc = host->frames_alloc(fr, times.size(), nv, err)) != 0)
		return rc;
	/* The joined mesh's triangles. */
	size_t v0 = 0, t = 0;
	for (const Instance &i : inst) {
		for (unsigned f = 0; f < i.mesh->mNumFaces; f++) {
			const aiFace &face = i.mesh->mFaces[f];
			if (face.mNumIndices != 3)
				continue;
			for (int k = 0; k < 3; k++)
				m->triangles[3 * t + k] = uint32_t(v0 + face.mIndices[k]);
			t++;
		}
		v0 += i.mesh->mNumVertices;
	}
	/* Each frame's positions. */
	std::vector<double> acc, sum;
	std::map<const aiNode *, aiMatrix4x4> g; /* every frame overwrites it */
	for (size_t f = 0; f < times.size(); f++) {
		globals(s->mRootNode, aiMatrix4x4(), chan, times[f], g);
		float *out = fr->positions + 3 * nv * f;
		v0 = 0;
		for (const Instance &i : inst) {
			const aiMesh *me = i.mesh;
			acc.assign(3 * (size_t)me->mNumVertices, 0.0);
			sum.assign(me->mNumVertices, 0.0);
			for (unsigned b = 0; b < me->mNumBones; b++) {
				const aiBone *bone = me->mBones[b];
				aiMatrix4x4 mb = g[i.bones[b]] * bone->mOffsetMatrix;
				for (unsigned w = 0; w < bone->mNumWeights; w++) {
					const aiVertexWeight &vw = bone->mWeights[w];
					if (!(vw.mWeight > 0))
						continue;
					aiVector3D p = mb * me->mVertices[vw.mVertexId];
					for (int k = 0; k < 3; k++)
						acc[3 * (size_t)vw.mVertexId + k] += (double)vw.mWeight * p[k];
					sum[vw.mVertexId] += vw.mWeight;
				}
			}
			const aiMatrix4x4 &gn = g[i.node];
			for (unsigned v = 0; v < me->mNumVertices; v++) {
				double p[3];
				if (sum[v] > 0) {
					for (int k = 0; k < 3; k++)
						p[k] = acc[3 * (size_t)v + k] / sum[v];
				} else {
					aiVector3D q = gn * me->mVertices[v];
					for (int k = 0; k < 3; k++)
						p[k] = q[k];
				}
				for (int k = 0; k < 3; k++) {
					float x = (float)p[k];
					if (!std::isfinite(x))
						return host->err_set(err, VDT_EINVAL,
						                   "frame %zu: vertex %zu has a non-finite coordinate", f,
						                   v0 + v);
					out[3 * (v0 + v) + k] = x;
				}
			}
			v0 += me->mNumVertices;
		}
	}
	memcpy(m->positions, fr->positions, 3 * nv * sizeof(float));
	return 0;
}

} // namespace

extern "C" int
vdt_asm_abi(void)
{
	vdt_cxx_thread_ready();
	return VDT_ASM_ABI;
}

extern "C" int
vdt_asm_read(const struct vdt_host *host, const char *path, const struct vdt_bake_opts *bo,
             struct vdt_mesh *m, struct vdt_frames *fr, struct vdt_err *err)
{
	int rc;

	memset(m, 0, sizeof(*m));
	memset(fr, 0, sizeof(*fr));
	/* No step that merges or drops vertices: the bones' weights are per
	 * vertex, and welding the seams is the caller's. */
	/* Assimp's own word for a file it cannot open is vaguer than errno's. */
	FILE *f = fopen(path, "rb");
	if (f == nullptr)
		return host->err_set(err, errno == ENOMEM ? VDT_ENOMEM : VDT_EIO, "%s",
		                     strerror(errno));
	fclose(f);
	const aiScene *s = aiImportFile(path, aiProcess_ValidateDataStructure | aiProcess_Triangulate |
	                                          aiProcess_SortByPType);
	if (s == nullptr) {
		/* Assimp catches its own exceptions, out of memory too, and
		 * says so as "bad_alloc", in errno's words, or not at all (its
		 * message lost for want of memory): a file it failed on while
		 * not even a little memory is left is no bad input. (Its
		 * string read in place: a copy could run out itself.) */
		const char *why = aiGetErrorString();
		size_t n = strlen(why);
		while (n > 0 && (why[n - 1] == '\n' || why[n - 1] == '.' || why[n - 1] == ' '))
			n--;
		void *room = malloc(65536);
		bool starved = room == nullptr;
		free(room);
		if (starved || strstr(why, "bad_alloc") || strstr(why, strerror(ENOMEM)))
			return host->err_set(err, VDT_ENOMEM, "out of memory");
		if (n == 0)
			return host->err_set(err, VDT_EFORMAT, "not a model Assimp reads");
		return host->err_set(err, VDT_EFORMAT, "%.*s", (int)n, why);
	}
	try {
		rc = bake(host, s, bo, m, fr, err);
	} catch (const std::bad_alloc &) {
		rc = host->err_set(err, VDT_ENOMEM, "out of memory");
	}
	aiReleaseImport(s);
	if (rc != 0) {
		host->mesh_free(m);
		host->frames_free(fr);
	}
	return rc;
}
