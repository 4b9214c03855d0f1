// The API page (/api/docs): the daemon's OpenAPI document rendered by Swagger UI (swagger-ui-dist's bundle, served by
// the daemon: nothing comes from the network), operations grouped by their tags. "Try it out" sends its requests from
// this origin with the console's session cookie, so they carry the logged-in user's role.
declare const SwaggerUIBundle: (options: Record<string, unknown>) => unknown;

SwaggerUIBundle({
  url: '/api/v1/openapi.json',
  dom_id: '#api-docs',
  validatorUrl: null, // the default sends the document to swagger.io to be checked
  deepLinking: true,
  docExpansion: 'list',
  defaultModelsExpandDepth: 0,
  displayOperationId: true,
});
